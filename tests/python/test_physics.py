# SPDX-License-Identifier: MIT
"""(d) Physics of the two_discs example, read straight from the file with h5py: two free discs,
no gravity, moving towards each other. Total momentum (from the frames and from the momentum
observable) stays at its initial value to 1e-9 of one disc's |p_x|, through the contact; the discs
approach, touch, separate; nothing is NaN."""

import h5py
import numpy as np
import pytest

REL = 1e-9


@pytest.fixture(scope="module")
def run(h5file):
    with h5py.File(h5file, "r") as f:
        pn = f["particles/nodes"]
        d = {
            "mass": pn["mass"][()],
            "species": pn["species"][()],
            "x": pn["position/value"][()],
            "v": pn["velocity/value"][()],
            "frame_step": pn["position/step"][()],
            "obs_step": f["observables/kinetic_energy/step"][()],
            "p_obs": f["observables/momentum/value"][()],
            "ke_obs": f["observables/kinetic_energy/value"][()],
            "contacts": f["observables/contact_count/value"][()],
            "fixed": f["bodies/fixed"][()],
            "kind": f["bodies/kind"][()],
            "gravity": f["loading/gravity"][()],
            "v0": f["bodies/initial_velocity"][()],
        }
    return d


def test_scenario(run):
    """The premises of the checks below: two free particles, no gravity, approaching."""
    assert len(run["fixed"]) == 2 and not run["fixed"].any() and not run["kind"].any()
    assert not run["gravity"].any()
    assert run["v0"][0, 0] > 0 > run["v0"][1, 0]
    np.testing.assert_array_equal(run["species"], np.sort(run["species"]))


def one_disc_px(run):
    m, sp, v = run["mass"], run["species"], run["v"]
    p = abs(np.sum(m[sp == 0] * v[0][sp == 0, 0]))
    assert p > 0
    return p


def test_momentum_from_frames_conserved(run):
    p_ref = one_disc_px(run)
    p = np.einsum("n,tnc->tc", run["mass"], run["v"])
    drift = np.abs(p - p[0]).max()
    assert drift <= REL * p_ref, "frame momentum drifts by %g (p_ref %g)" % (drift, p_ref)


def test_momentum_observable_conserved_through_contact(run):
    p_ref = one_disc_px(run)
    p, contacts = run["p_obs"], run["contacts"]
    assert (contacts > 0).any(), "the discs never touched"
    during = contacts > 0
    assert np.abs(p[during] - p[0]).max() <= REL * p_ref
    assert np.abs(p - p[0]).max() <= REL * p_ref
    # The observable agrees with the frames at the frame steps (every frame step is observed).
    p_frames = np.einsum("n,tnc->tc", run["mass"], run["v"])
    rows = np.searchsorted(run["obs_step"], run["frame_step"])
    assert (rows < len(run["obs_step"])).all()
    np.testing.assert_array_equal(run["obs_step"][rows], run["frame_step"])
    np.testing.assert_allclose(p[rows], p_frames, rtol=0, atol=REL * p_ref)


def centre_distance(run):
    m, sp, x = run["mass"], run["species"], run["x"]
    c = [np.einsum("n,tnc->tc", m[sp == b], x[:, sp == b]) / m[sp == b].sum() for b in (0, 1)]
    return np.linalg.norm(c[1] - c[0], axis=1)


def test_discs_approach_touch_and_separate(run):
    d = centre_distance(run)
    contacts = run["contacts"]
    assert d[1] < d[0], "the discs do not approach"
    assert d.min() < d[0]
    assert (contacts > 0).any(), "the discs never touched"
    assert contacts[-1] == 0, "the discs are still in contact at the end"
    first = np.argmax(contacts > 0)
    assert first > 0, "in contact from the start"
    assert d[-1] > d[-2], "the discs do not separate at the end"
    assert np.argmin(d) not in (0, len(d) - 1)


def test_no_energy_created(run):
    """Kinetic energy after the collision does not exceed the initial one (restitution <= 1)."""
    ke = run["ke_obs"]
    assert ke[-1] <= ke[0] * (1 + 1e-6)
    assert ke[-1] > 0


def test_kinetic_energy_observable_matches_frames(run):
    rows = np.searchsorted(run["obs_step"], run["frame_step"])
    assert (rows < len(run["obs_step"])).all()
    np.testing.assert_array_equal(run["obs_step"][rows], run["frame_step"])
    ke_frames = 0.5 * np.einsum("n,tnc->t", run["mass"], run["v"] ** 2)
    np.testing.assert_allclose(run["ke_obs"][rows], ke_frames, rtol=1e-12)


def test_no_nan_anywhere(h5file):
    bad = []

    def visit(name, obj):
        if isinstance(obj, h5py.Dataset) and obj.dtype.kind == "f":
            if not np.isfinite(obj[()]).all():
                bad.append(name)

    with h5py.File(h5file, "r") as f:
        f.visititems(visit)
    assert not bad, "non-finite values in %s" % bad

# SPDX-License-Identifier: MIT
"""Nothing outside the run is touched, nothing inside it is lost (issue 27).

Classes of inputs, each asserting the exit code, the culprit in the message and that every file
that existed before is byte-identical afterwards (sha256):
1. outputs that are not regular files (device, FIFO, socket, directory), that are an input the run
   reads under another name (symlink, hard link, the CSV or .msh a scene or deck names), or a
   pd-file holding results; side files (.reserve, .lock) planted as links;
2. locks: every name of a file is one lock (symlink, hard link, relative path; the holder an MPI
   run), a lock file naming a live but unrelated pid does not block;
3. refusals of every tool leave the file byte for byte (no /provenance entry);
4. SIGINT and SIGHUP stop pd-solve like SIGTERM (checkpoint, exit 75);
5. a pd-file that points elsewhere (external link, virtual dataset) is refused naming the path;
6. inputs that are not regular files (FIFO, /dev/zero) are refused, never read (no hang)."""

import os
import pathlib
import shutil
import signal
import socket
import stat
import subprocess
import time

import numpy as np
import pytest

from test_safety import (  # noqa: F401
    SRC,
    assert_refused,
    bin_dir,
    copy,
    made,
    run,
    sha,
    write_scene,
)

h5py = pytest.importorskip("h5py")

SHARED = pathlib.Path(os.environ.get("PD_SHARED_DIR", SRC.parent / "shared"))
MPI_ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMP_NUM_THREADS="1", OMPI_MCA_rmaps_base_oversubscribe="1")


def digests(*paths):
    return {str(p): sha(p) for p in paths}


def provenance_rows(f):
    with h5py.File(f, "r") as h:
        return len(h["provenance"]) if "provenance" in h else 0


def deck_dir(tmp_path, name):
    src = SHARED / "data" / "peridem" / name
    if not src.is_dir():
        pytest.skip(f"no PeriDEM deck {src} (set PD_SHARED_DIR)")
    d = tmp_path / name
    shutil.copytree(src, d)
    return d


# ---------------------------------------------------------------------------------------------
# 1. Outputs


def special_file(kind, path):
    """Makes a FIFO, a socket or a character device (a copy of /dev/null's numbers) at path."""
    if kind == "fifo":
        os.mkfifo(path)
        return None
    if kind == "socket":
        s = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
        s.bind(str(path))
        return s
    if os.geteuid() != 0:
        pytest.skip("making a device node needs root")
    os.mknod(path, stat.S_IFCHR | 0o666, os.makedev(1, 3))
    return None


@pytest.mark.parametrize("kind", ["fifo", "socket", "device"])
@pytest.mark.parametrize("option", ["-o", "--write-scene", "--preview"])
def test_pack_output_not_a_regular_file(bin_dir, tmp_path, kind, option):
    scene = write_scene(tmp_path / "scene.json")
    target = tmp_path / "target"
    keep = special_file(kind, target)
    mode = os.lstat(target).st_mode
    args = ["-o", target] if option == "-o" else ["-o", tmp_path / "out.h5", option, target]
    r = run(bin_dir / "pd-pack", scene, *args, timeout=60)
    assert_refused(r, option, "not a regular file")
    assert os.lstat(target).st_mode == mode  # still the FIFO, socket or device
    assert not (tmp_path / "out.h5").exists()
    if keep:
        keep.close()


@pytest.mark.parametrize("alias", ["symlink", "hardlink"])
def test_pack_output_is_the_scene_through_a_link(bin_dir, tmp_path, alias):
    scene = write_scene(tmp_path / "scene.json")
    link = tmp_path / "out.h5"
    (os.symlink if alias == "symlink" else os.link)(scene, link)
    before = sha(scene)
    r = run(bin_dir / "pd-pack", scene, "-o", link)
    assert_refused(r, "-o", "scene.json")
    assert sha(scene) == before


def csv_scene(tmp_path):
    csv = tmp_path / "grains.csv"
    csv.write_text("x,y,z,r,orientation,shape\n-1.15e-3,0,0,1e-3,0,0\n1.15e-3,0,0,1e-3,0,0\n")
    scene = write_scene(tmp_path / "scene.json", particles=[
        {"generate": "csv", "file": "grains.csv", "shapes": ["disc"], "material": "m1"}])
    return scene, csv


@pytest.mark.parametrize("option", ["-o", "--write-scene", "--preview"])
def test_pack_output_is_the_particle_csv(bin_dir, tmp_path, option):
    scene, csv = csv_scene(tmp_path)
    r = run(bin_dir / "pd-pack", scene, "-o", tmp_path / "ok.h5", "-q")
    assert r.returncode == 0, r.stderr  # the scene itself is fine
    link = tmp_path / "alias.csv"
    os.symlink(csv, link)
    before = digests(csv, scene)
    args = ["-o", link] if option == "-o" else ["-o", tmp_path / "out.h5", option, link]
    r = run(bin_dir / "pd-pack", scene, *args)
    assert_refused(r, option, "particle file", "grains.csv")
    assert digests(csv, scene) == before
    assert not (tmp_path / "out.h5").exists()


@pytest.mark.parametrize("target", ["mesh_cir_1_0.msh", "particle_locations_0.csv"])
@pytest.mark.parametrize("option", ["-o", "--write-scene"])
def test_pack_output_is_a_deck_file(bin_dir, tmp_path, option, target):
    d = deck_dir(tmp_path, "twop_circ")
    files = sorted(p for p in d.iterdir())
    before = digests(*files)
    args = ["-o", d / target] if option == "-o" else ["-o", tmp_path / "out.h5", option,
                                                        d / target]
    r = run(bin_dir / "pd-pack", "--from-peridem", d / "input_0.yaml", *args)
    assert_refused(r, option, target)
    assert digests(*files) == before
    assert not (tmp_path / "out.h5").exists()


def test_pack_output_holding_results(bin_dir, made, tmp_path):
    f = tmp_path / "solved.h5"
    shutil.copy(made["solved"], f)
    scene = write_scene(tmp_path / "scene.json")
    before = sha(f)
    r = run(bin_dir / "pd-pack", scene, "-o", f)
    assert_refused(r, "-o", "--overwrite", "results")
    assert sha(f) == before
    r = run(bin_dir / "pd-pack", scene, "-o", f, "--overwrite", "-q")
    assert r.returncode == 0, r.stderr
    with h5py.File(f, "r") as h:
        assert "particles" not in h and "checkpoints" not in h
    r = run(bin_dir / "pd-pack", scene, "-o", f, "-q")  # a packed file holds no results
    assert r.returncode == 0, r.stderr


@pytest.mark.parametrize("side", [".reserve", ".lock"])
@pytest.mark.parametrize("alias", ["symlink", "hardlink"])
def test_side_file_planted_as_a_link(bin_dir, copy, tmp_path, side, alias):
    f = copy("base")
    notes = tmp_path / "notes.txt"
    notes.write_text("my notes\n")
    (os.symlink if alias == "symlink" else os.link)(notes, str(f) + side)
    r = run(bin_dir / "pd-solve", f, "--steps", 10, "-q")
    assert r.returncode == 0, r.stderr
    assert notes.read_text() == "my notes\n"
    assert not os.path.lexists(str(f) + ".reserve")


@pytest.mark.parametrize("name, kind", [("observables.csv", "fifo"), ("solved.pvd", "dir"),
                                        ("grains.csv", "socket")])
def test_post_product_not_a_regular_file(bin_dir, copy, tmp_path, name, kind):
    f = copy("solved")
    out = tmp_path / "post"
    out.mkdir()
    target = out / name
    keep = target.mkdir() if kind == "dir" else special_file(kind, target)
    mode = os.lstat(target).st_mode
    before = sha(f)
    r = run(bin_dir / "pd-post", f, "-o", out, timeout=60)
    assert_refused(r, name, "not a regular file")
    assert os.lstat(target).st_mode == mode and sha(f) == before
    assert sorted(p.name for p in out.iterdir()) == [name]
    if keep:
        keep.close()


def test_post_product_planted_as_a_link(bin_dir, copy, tmp_path):
    f = copy("solved")
    out = tmp_path / "post"
    out.mkdir()
    notes = tmp_path / "notes.txt"
    notes.write_text("my notes\n")
    for name in ("observables.csv", "observables.csv.tmp", "solved.pvd.tmp"):
        os.symlink(notes, out / name)
    r = run(bin_dir / "pd-post", f, "-o", out, "-q", timeout=120)
    assert r.returncode == 0, r.stderr
    assert notes.read_text() == "my notes\n"
    assert (out / "observables.csv").is_file() and not (out / "observables.csv").is_symlink()


# ---------------------------------------------------------------------------------------------
# 2. Locks


def mpirun(*args):
    return ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", "2", *map(str, args)]


def children(pid):
    with open(f"/proc/{pid}/task/{pid}/children") as fh:
        return [int(c) for c in fh.read().split()]


def test_lock_holds_for_every_name_under_mpi(bin_dir, made, tmp_path):
    f = tmp_path / "f.h5"
    shutil.copy(made["base"], f)
    (tmp_path / "sub").mkdir()
    sym = tmp_path / "sym.h5"
    os.symlink(f, sym)
    hard = tmp_path / "hard.h5"
    os.link(f, hard)
    p = subprocess.Popen(mpirun(bin_dir / "pd-solve", f, "--final-time", 1.0,
                                "--progress-every", 1),
                         env=MPI_ENV, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    try:
        out = []
        for line in p.stdout:  # the run's phase 3 has begun
            out.append(line)
            if line.startswith("step "):
                break
        assert p.poll() is None, "".join(out)
        names = {"symlink": sym, "hard link": hard, "relative": "sub/../f.h5"}
        refused = 0
        for how, name in names.items():
            cases = {
                "pd-solve": [bin_dir / "pd-solve", name, "--restart"],
                "mpirun pd-solve": mpirun(bin_dir / "pd-solve", name, "--overwrite"),
                "pd-partition": [bin_dir / "pd-partition", name, "-n", 2],
                "pd-post": [bin_dir / "pd-post", name, "-o", tmp_path / "post"],
                "pd-pack -o": [bin_dir / "pd-pack", SRC / "examples/two_discs/scene.json",
                               "-o", name],
            }
            for tool, cmd in cases.items():
                r = subprocess.run(list(map(str, cmd)), cwd=tmp_path, env=MPI_ENV,
                                   capture_output=True, text=True, timeout=120)
                assert r.returncode == 2, (how, tool, r.stdout, r.stderr)
                assert "in use by" in r.stderr, (how, tool, r.stderr)
                refused += 1
        print(f"refused through another name of the file: {refused} of {refused}")
        assert not (tmp_path / "post").exists()
        os.kill(children(p.pid)[-1], signal.SIGTERM)
        p.wait(timeout=120)
        assert p.returncode == 75
    finally:
        if p.poll() is None:
            p.kill()
    assert not pathlib.Path(str(f) + ".lock").exists()
    r = run(bin_dir / "pd-solve", sym, "--restart", "--final-time", 1.0, "--steps", 10, "-q")
    assert r.returncode == 0, r.stderr


def live_unrelated_pid():
    """A process that is alive and is no pdgrain tool (it plays a reused pid)."""
    return subprocess.Popen(["sleep", "60"])


@pytest.mark.parametrize("started", [None, 12345])
def test_lock_naming_a_reused_pid_does_not_block(bin_dir, copy, tmp_path, started):
    f = copy("base")
    other = live_unrelated_pid()
    try:
        extra = "" if started is None else f" {started}"
        line = f"{other.pid} {socket.gethostname()} pd-solve {int(time.time())}{extra}\n"
        lock = pathlib.Path(str(f) + ".lock")
        lock.write_text(line)
        r = run(bin_dir / "pd-solve", f, "--steps", 10, "-q")
        assert r.returncode == 0, r.stderr
        assert not lock.exists()
        # pd-pack onto a new output: no file to hold a record lock, the start time decides
        out = tmp_path / "new.h5"
        pathlib.Path(str(out) + ".lock").write_text(
            f"{other.pid} {socket.gethostname()} pd-pack {int(time.time())} 12345\n")
        r = run(bin_dir / "pd-pack", write_scene(tmp_path / "s.json"), "-o", out, "-q")
        assert r.returncode == 0, r.stderr
        assert out.is_file()
    finally:
        other.kill()
        other.wait()


def test_lock_released_when_the_holder_is_killed(bin_dir, copy):
    f = copy("base")
    p = subprocess.Popen([str(bin_dir / "pd-solve"), str(f), "--final-time", "1.0",
                          "--progress-every", "1"],
                         stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    for line in p.stdout:
        if line.startswith("step "):
            break
    r = run(bin_dir / "pd-partition", f, "-n", 2)
    assert_refused(r, "in use by")
    p.kill()
    p.wait()
    assert pathlib.Path(str(f) + ".lock").exists()  # left behind by kill -9: stale
    r = run(bin_dir / "pd-solve", f, "--overwrite", "--steps", 5, "-q")
    assert r.returncode == 0, r.stderr


# ---------------------------------------------------------------------------------------------
# 3. Refusals leave the file byte for byte (no /provenance entry)


REFUSALS = [
    ("pd-post", "solved", ["--crack-origin", "1,2,3,4"], "--crack-origin"),
    ("pd-post", "solved", ["--check", "--bogus"], "--bogus"),
    ("pd-post", "nan_frames", [], "/particles/nodes/position/value"),
    ("pd-post", "damaged", [], "/materials/m1"),
    ("pd-post-check", "damaged", [], "/materials/m1"),
    ("pd-partition", "base", ["-n", 0], "-n"),
    ("pd-partition", "damaged", ["-n", 2], "/materials/m1"),
    ("pd-solve", "solved", [], "--overwrite"),
    ("pd-solve", "reserve_dir", ["--steps", 5], ".reserve"),
    ("pd-solve", "damaged", [], "/materials/m1"),
]


@pytest.mark.parametrize("tool, which, args, culprit", REFUSALS,
                         ids=[f"{t}:{w}:{' '.join(map(str, a))}" for t, w, a, _ in REFUSALS])
def test_refusal_leaves_the_file_byte_for_byte(bin_dir, copy, tmp_path, tool, which, args,
                                               culprit):
    f = copy("solved" if which in ("nan_frames", "solved") else "base")
    if which == "nan_frames":
        with h5py.File(f, "r+") as h:
            v = h["particles/nodes/position/value"]
            a = v[()]
            a[0, 3, 0] = np.nan
            v[...] = a
    elif which == "damaged":
        with h5py.File(f, "r+") as h:
            h["materials/m1/density"][()] = -1.0
    elif which == "reserve_dir":
        os.mkdir(str(f) + ".reserve")
    rows = provenance_rows(f)
    before = sha(f)
    exe = "pd-post" if tool == "pd-post-check" else tool
    extra = ["--check"] if tool == "pd-post-check" else []
    if exe == "pd-post" and not extra and "--check" not in args:
        extra = ["-o", tmp_path / "post"]
    r = run(bin_dir / exe, f, *extra, *args, timeout=120)
    assert_refused(r, culprit)
    assert sha(f) == before and provenance_rows(f) == rows


# ---------------------------------------------------------------------------------------------
# 4. Signals


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGHUP, signal.SIGTERM])
def test_stop_signal_checkpoints_and_exits_75(bin_dir, copy, sig):
    f = copy("base")
    p = subprocess.Popen([str(bin_dir / "pd-solve"), str(f), "--final-time", "1.0",
                          "--progress-every", "0.2"],
                         stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    out = []
    for line in p.stdout:
        out.append(line)
        if line.startswith("step "):
            break
    p.send_signal(sig)
    out.append(p.communicate(timeout=120)[0])
    text = "".join(out)
    assert p.returncode == 75, text
    assert signal.Signals(sig).name in text
    with h5py.File(f, "r") as h:
        assert "latest" in h["checkpoints"].attrs
        last = sorted(h["provenance"])[-1]
        assert int(h["provenance"][last].attrs["exit_status"]) == 75
    r = run(bin_dir / "pd-solve", f, "--restart", "--final-time", 1.0, "--steps", 5, "-q")
    assert r.returncode == 0, r.stderr


# ---------------------------------------------------------------------------------------------
# 5. Files that point elsewhere


def external_link(f, tmp_path):
    other = tmp_path / "other.h5"
    with h5py.File(f, "r") as src, h5py.File(other, "w") as dst:
        src.copy("checkpoints", dst)
    with h5py.File(f, "r+") as h:
        del h["checkpoints"]
        h["checkpoints"] = h5py.ExternalLink(str(other), "/checkpoints")
    return "/checkpoints", other


def virtual_dataset(f, tmp_path):
    other = tmp_path / "other.h5"
    with h5py.File(f, "r") as src, h5py.File(other, "w") as dst:
        dst["v"] = src["nodes/volume"][()]
    with h5py.File(f, "r+") as h:
        n = h["nodes/volume"].shape[0]
        layout = h5py.VirtualLayout(shape=(n,), dtype="f8")
        layout[:] = h5py.VirtualSource(str(other), "v", shape=(n,))
        del h["nodes/volume"]
        h.create_virtual_dataset("nodes/volume", layout)
    return "/nodes/volume", other


@pytest.mark.parametrize("make", [external_link, virtual_dataset])
@pytest.mark.parametrize("tool", ["pd-solve", "pd-post", "pd-post-check", "pd-partition"])
def test_file_pointing_elsewhere_refused(bin_dir, copy, tmp_path, make, tool):
    f = copy("solved")
    path, other = make(f, tmp_path)
    before = digests(f, other)
    args = {
        "pd-solve": ["pd-solve", f, "--restart", "--steps", 5],
        "pd-post": ["pd-post", f, "-o", tmp_path / "post"],
        "pd-post-check": ["pd-post", "--check", f],
        "pd-partition": ["pd-partition", f, "-n", 2],
    }[tool]
    r = run(bin_dir / args[0], *args[1:], timeout=60)
    assert_refused(r, path)
    assert digests(f, other) == before


# ---------------------------------------------------------------------------------------------
# 6. Inputs that are not regular files


@pytest.mark.parametrize("source", ["fifo", "/dev/zero"])
@pytest.mark.parametrize("tool", ["pd-pack", "pd-solve", "pd-partition", "pd-post",
                                  "pd-post-check", "csv", "msh"])
def test_input_not_a_regular_file(bin_dir, tmp_path, tool, source):
    if source == "fifo":
        src = tmp_path / "in.fifo"
        os.mkfifo(src)
    else:
        src = pathlib.Path(source)
    out = tmp_path / "out.h5"
    if tool in ("csv", "msh"):
        link = tmp_path / ("grains.csv" if tool == "csv" else "disc.msh")
        os.symlink(src, link)
        changes = ({"particles": [{"generate": "csv", "file": "grains.csv", "shapes": ["disc"],
                                   "material": "m1"}]} if tool == "csv" else
                   {"shapes": {"disc": {"type": "circle", "radius": 1e-3, "mesh": "file",
                                        "file": "disc.msh"}}})
        # --allow-outside: /dev/zero lies outside the scene's folder (refused as such without
        # it, test_run_faults.py); with it the link is followed to a file that is not regular
        args = ["pd-pack", write_scene(tmp_path / "scene.json", **changes), "-o", out,
                "--allow-outside"]
        culprit = link.name
    else:
        args = {
            "pd-pack": ["pd-pack", src, "-o", out],
            "pd-solve": ["pd-solve", src],
            "pd-partition": ["pd-partition", src, "-n", 2],
            "pd-post": ["pd-post", src, "-o", tmp_path / "post"],
            "pd-post-check": ["pd-post", "--check", src],
        }[tool]
        culprit = str(src)
    r = run(bin_dir / args[0], *args[1:], timeout=30)
    assert_refused(r, culprit, "not a regular file")
    assert not out.exists() and not (tmp_path / "post").exists()
    if source == "fifo":
        assert stat.S_ISFIFO(os.lstat(src).st_mode)


# ---------------------------------------------------------------------------------------------
# 7. Accepted but wrong -> refused: bond lists, condition node lists, deck integers


def damage_bonds(f, how):
    with h5py.File(f, "r+") as h:
        off = h["bonds/offsets"][()]
        nb = h["bonds/neighbor"][()]
        row = nb[off[0]:off[1]]
        if how == "duplicate":
            nb[off[0]] = row[1]
        else:  # asymmetric: node 0 names a node that does not name it back
            far = next(k for k in range(len(off) - 1) if k != 0 and k not in row)
            nb[off[0]] = far
        h["bonds/neighbor"][...] = nb


@pytest.mark.parametrize("how, culprit", [("duplicate", "twice"), ("asymmetric", "asymmetric")])
@pytest.mark.parametrize("tool", ["pd-solve", "pd-partition", "pd-post-check"])
def test_bad_bond_list_refused(bin_dir, copy, tool, how, culprit):
    f = copy("base")
    damage_bonds(f, how)
    before = sha(f)
    args = {
        "pd-solve": ["pd-solve", f, "--steps", 5],
        "pd-partition": ["pd-partition", f, "-n", 2],
        "pd-post-check": ["pd-post", "--check", f],
    }[tool]
    r = run(bin_dir / args[0], *args[1:], timeout=60)
    assert_refused(r, "/bonds/neighbor", culprit)
    assert sha(f) == before


@pytest.mark.parametrize("tool", ["pd-solve", "pd-post-check"])
def test_node_repeated_in_a_condition_refused(bin_dir, tmp_path, tool):
    scene = write_scene(tmp_path / "scene.json", loading={"gravity": [0, 0], "conditions": [
        {"name": "push", "kind": "force_density", "particles": [0], "components": ["x"],
         "value": 1e3}]})
    f = tmp_path / "c.h5"
    r = run(bin_dir / "pd-pack", scene, "-o", f, "-q")
    assert r.returncode == 0, r.stderr
    with h5py.File(f, "r+") as h:
        g = h["loading/conditions"]
        p = f"loading/conditions/{sorted(g)[0]}/nodes"
        nodes, attrs = h[p][()], dict(h[p].attrs)
        del h[p]
        h[p] = np.concatenate([nodes, np.repeat(nodes[:1], 7)])  # node listed 8 times
        h[p].attrs.update(attrs)
    before = sha(f)
    args = ["pd-solve", f, "--steps", 5] if tool == "pd-solve" else ["pd-post", "--check", f]
    r = run(bin_dir / args[0], *args[1:], timeout=60)
    assert_refused(r, "/nodes", "more than once")
    assert sha(f) == before


@pytest.mark.parametrize("old, new, culprit", [
    ("  Sets: 2", "  Sets: 1e12", "Displacement_BC.Sets"),
    ("  Sets: 2", "  Sets: 1.5", "Displacement_BC.Sets"),
    ("  Dimension: 2", "  Dimension: 4294967298", "Model.Dimension"),
    ("      Type: 1", "      Type: 1e10", "Influence_Function.Type"),
    ("    Gc: 5.000000e+02", "    Gc: -50", "Gc"),
])
def test_deck_integers_and_values_checked_before_use(bin_dir, tmp_path, old, new, culprit):
    d = deck_dir(tmp_path, "single_particle_circle")
    deck = d / "input_0.yaml"
    text = deck.read_text()
    assert old in text
    deck.write_text(text.replace(old, new, 1))
    out = tmp_path / "out.h5"
    r = run(bin_dir / "pd-pack", "--from-peridem", deck, "-o", out)
    assert_refused(r, culprit)
    assert not out.exists()


def test_csv_error_never_echoes_the_content(bin_dir, tmp_path):
    secret = tmp_path / "secret.txt"
    secret.write_text("USER=me\nAPI_TOKEN=abc123\n")  # the first line passes for a header
    scene = write_scene(tmp_path / "scene.json", particles=[
        {"generate": "csv", "file": "secret.txt", "shapes": ["disc"], "material": "m1"}])
    r = run(bin_dir / "pd-pack", scene, "-o", tmp_path / "out.h5")
    assert_refused(r, "secret.txt", "byte")
    assert "API_TOKEN" not in r.stderr and "abc123" not in r.stderr


def test_scene_error_never_echoes_the_content(bin_dir, tmp_path):
    secret = tmp_path / "secret.json"
    secret.write_text("API_TOKEN=abc123\n")
    r = run(bin_dir / "pd-pack", secret, "-o", tmp_path / "out.h5")
    assert_refused(r, "secret.json", "not valid JSON")
    assert "API_TOKEN" not in r.stderr and "abc123" not in r.stderr

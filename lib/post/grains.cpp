// SPDX-License-Identifier: MIT
// grains.csv writer (see grains.hpp). Rotation: 2D, the angle minimising sum_i w_i |R p_i - q_i|^2
// (p = reference, q = current node offsets from the centres of mass, w = volume) is
// atan2(sum w p x q, sum w p . q); 3D, the Kabsch rotation from the SVD of sum w p q^T.
#include "post/grains.hpp"

#include "core/errors.hpp"
#include "h5/file.hpp"
#include "post/text_out.hpp"
#include "store/checkpoint_io.hpp"
#include "store/frames.hpp"
#include "store/schema.hpp"

#include <Eigen/Dense>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <numeric>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace pd::post {

namespace {

/// Broken bonds (each pair once) and fragments (connected components of intact bonds) per body.
struct BondState {
    std::vector<std::int64_t> broken, fragments;
};

BondState bond_state(const model::Model& m, const std::vector<std::uint8_t>& alive) {
    const auto nb = m.bodies.node_offsets.size() - 1;
    const auto n = m.nodes.volume.size();
    std::vector<std::int64_t> parent(n);
    std::iota(parent.begin(), parent.end(), 0);
    const auto find = [&](std::int64_t i) {
        while (parent[i] != i)
            i = parent[i] = parent[parent[i]];
        return i;
    };
    BondState s{std::vector<std::int64_t>(nb, 0), std::vector<std::int64_t>(nb, 0)};
    for (std::size_t i = 0; i < n; ++i)
        for (auto e = m.bonds.offsets[i]; e < m.bonds.offsets[i + 1]; ++e) {
            const auto j = static_cast<std::int64_t>(m.bonds.neighbor[e]);
            if (!alive[e]) {
                s.broken[m.nodes.body[i]] += 1; // counted from both ends, halved below
                continue;
            }
            const auto a = find(static_cast<std::int64_t>(i)), b = find(j);
            if (a != b)
                parent[std::max(a, b)] = std::min(a, b);
        }
    for (std::size_t b = 0; b < nb; ++b) {
        s.broken[b] /= 2;
        for (auto i = m.bodies.node_offsets[b]; i < m.bodies.node_offsets[b + 1]; ++i)
            if (find(i) == i)
                ++s.fragments[b];
    }
    return s;
}

/// Rotation angle (rad) of the best rigid fit; p, q are the centred reference/current offsets.
double kabsch_angle(const Eigen::Matrix3d& h) {
    Eigen::JacobiSVD<Eigen::Matrix3d> svd(h, Eigen::ComputeFullU | Eigen::ComputeFullV);
    const Eigen::Matrix3d u = svd.matrixU(), v = svd.matrixV();
    Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
    d(2, 2) = (v * u.transpose()).determinant() < 0 ? -1.0 : 1.0;
    const Eigen::Matrix3d r = v * d * u.transpose();
    return std::acos(std::clamp((r.trace() - 1.0) / 2.0, -1.0, 1.0));
}

/// Which per-node fields the frames carry besides the positions.
struct Has {
    bool v = false, phi = false, frag = false, broken = false;
};

/// Reference state: volume and volume-weighted centre per body (the density is uniform within
/// a body), bond count per node.
struct Reference {
    std::vector<double> vol, c0;
    std::vector<std::int64_t> degree;
};

Reference reference(const model::Model& m) {
    const auto n = m.nodes.volume.size();
    const auto nb = m.bodies.node_offsets.size() - 1;
    Reference r{std::vector<double>(nb, 0), std::vector<double>(3 * nb, 0),
                std::vector<std::int64_t>(n)};
    for (std::size_t b = 0; b < nb; ++b) {
        for (auto i = m.bodies.node_offsets[b]; i < m.bodies.node_offsets[b + 1]; ++i) {
            r.vol[b] += m.nodes.volume[i];
            for (int d = 0; d < 3; ++d)
                r.c0[3 * b + d] += m.nodes.volume[i] * m.nodes.x0[3 * i + d];
        }
        for (int d = 0; d < 3 && r.vol[b] > 0; ++d)
            r.c0[3 * b + d] /= r.vol[b];
    }
    for (std::size_t i = 0; i < n; ++i)
        r.degree[i] = m.bonds.offsets[i + 1] - m.bonds.offsets[i];
    return r;
}

/// The fields of frame k (empty where the file has none), their lengths checked.
struct FrameFields {
    std::vector<double> x, v, phi, frag, brk;
};

FrameFields read_frame(const h5::File& f, const store::FrameReader& frames, std::size_t k,
                       const Has& has, std::size_t n) {
    FrameFields fr;
    fr.x = frames.read("position", k);
    fr.v = has.v ? frames.read("velocity", k) : std::vector<double>{};
    fr.phi = has.phi ? frames.read("damage", k) : std::vector<double>{};
    if (fr.x.size() != 3 * n || (has.v && fr.v.size() != 3 * n) || (has.phi && fr.phi.size() != n))
        throw SchemaError(f.name(), store::path::particles,
                          fmt::format("frame {} has a field of the "
                                      "wrong length (n = {})",
                                      k, n));
    fr.frag = has.frag ? frames.read("fragment", k) : std::vector<double>{};
    fr.brk = has.broken ? frames.read("broken_bonds", k) : std::vector<double>{};
    return fr;
}

/// One row of grains.csv: the values of a body at a frame (empty optionals: empty cells).
struct GrainRow {
    std::int64_t step = 0;
    double time = 0;
    std::size_t body = 0;
    double com[3] = {0, 0, 0};
    std::optional<double> vcom[3];
    double rotation = 0;
    std::optional<double> damage, broken_est;
    std::optional<std::int64_t> broken, fragments;
};

std::string g17(std::optional<double> v) {
    return v ? fmt::format("{:.17g}", *v) : std::string();
}
std::string integer(std::optional<std::int64_t> v) {
    return v ? fmt::format("{}", *v) : std::string();
}

/// The columns of grains.csv, in order: header name and cell text.
using Column = std::pair<const char*, std::string (*)(const GrainRow&)>;
constexpr Column columns[] = {
    {"step", [](const GrainRow& r) { return fmt::format("{}", r.step); }},
    {"time", [](const GrainRow& r) { return g17(r.time); }},
    {"body", [](const GrainRow& r) { return fmt::format("{}", r.body); }},
    {"com_x", [](const GrainRow& r) { return g17(r.com[0]); }},
    {"com_y", [](const GrainRow& r) { return g17(r.com[1]); }},
    {"com_z", [](const GrainRow& r) { return g17(r.com[2]); }},
    {"vcom_x", [](const GrainRow& r) { return g17(r.vcom[0]); }},
    {"vcom_y", [](const GrainRow& r) { return g17(r.vcom[1]); }},
    {"vcom_z", [](const GrainRow& r) { return g17(r.vcom[2]); }},
    {"rotation", [](const GrainRow& r) { return g17(r.rotation); }},
    {"damage", [](const GrainRow& r) { return g17(r.damage); }},
    {"broken_bonds", [](const GrainRow& r) { return integer(r.broken); }},
    {"fragments", [](const GrainRow& r) { return integer(r.fragments); }},
    {"broken_bonds_est", [](const GrainRow& r) { return g17(r.broken_est); }},
};

/// Centre of mass, its velocity, volume-weighted damage and the broken-bond estimate of body b.
void measure(const model::Model& m, const Reference& ref, const FrameFields& fr, const Has& has,
             std::size_t b, GrainRow& row) {
    const auto lo = m.bodies.node_offsets[b], hi = m.bodies.node_offsets[b + 1];
    double c[3] = {0, 0, 0}, vc[3] = {0, 0, 0}, dmg = 0, est = 0;
    for (auto i = lo; i < hi; ++i) {
        const double w = m.nodes.volume[i];
        for (int d = 0; d < 3; ++d) {
            c[d] += w * fr.x[3 * i + d];
            if (has.v)
                vc[d] += w * fr.v[3 * i + d];
        }
        if (has.phi) {
            dmg += w * fr.phi[i];
            est += fr.phi[i] * static_cast<double>(ref.degree[i]);
        }
    }
    const double wb = ref.vol[b] > 0 ? ref.vol[b] : 1.0;
    for (int d = 0; d < 3; ++d) {
        row.com[d] = c[d] / wb;
        if (has.v)
            row.vcom[d] = vc[d] / wb;
    }
    if (has.phi) {
        row.damage = dmg / wb;
        row.broken_est = est / 2;
    }
}

/// Rotation (rad) of the rigid fit of body b about its centres of mass; 2D unwrapped in time
/// from last_angle (updated).
double rotation(const model::Model& m, const Reference& ref, const FrameFields& fr, std::size_t b,
                const double* c, double& last_angle) {
    Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
    for (auto i = m.bodies.node_offsets[b]; i < m.bodies.node_offsets[b + 1]; ++i) {
        const Eigen::Vector3d p(m.nodes.x0[3 * i] - ref.c0[3 * b],
                                m.nodes.x0[3 * i + 1] - ref.c0[3 * b + 1],
                                m.nodes.x0[3 * i + 2] - ref.c0[3 * b + 2]);
        const Eigen::Vector3d q(fr.x[3 * i] - c[0], fr.x[3 * i + 1] - c[1], fr.x[3 * i + 2] - c[2]);
        h += m.nodes.volume[i] * p * q.transpose();
    }
    if (m.dimension != 2)
        return kabsch_angle(h);
    double angle = std::atan2(h(0, 1) - h(1, 0), h(0, 0) + h(1, 1));
    const double two_pi = 2 * std::numbers::pi;
    angle += two_pi * std::round((last_angle - angle) / two_pi);
    last_angle = angle;
    return angle;
}

/// Broken bonds and fragments of body b: from the frame fields, else exact at the checkpoint.
void bond_counts(const model::Model& m, const FrameFields& fr, const Has& has, std::size_t b,
                 const BondState* exact, GrainRow& row) {
    const auto lo = m.bodies.node_offsets[b], hi = m.bodies.node_offsets[b + 1];
    if (has.broken) {
        double nb2 = 0;
        for (auto i = lo; i < hi; ++i)
            nb2 += fr.brk[static_cast<std::size_t>(i)];
        row.broken = static_cast<std::int64_t>(nb2 / 2);
    } else if (exact) {
        row.broken = exact->broken[b];
    }
    if (has.frag) {
        std::vector<double> ids(fr.frag.begin() + lo, fr.frag.begin() + hi);
        std::sort(ids.begin(), ids.end());
        row.fragments = std::unique(ids.begin(), ids.end()) - ids.begin();
    } else if (exact) {
        row.fragments = exact->fragments[b];
    }
}

/// The method, stated in a comment line after the table: numpy's genfromtxt(names=True) would
/// take a leading comment line for the header.
std::string method_note(const h5::File& f, const model::Model& m, const Has& has,
                        const std::optional<store::Checkpoint>& ckpt) {
    return fmt::format(
        "# pd-post grains.csv from {}; volume-weighted centre of mass (m) and its velocity "
        "(m s-1); rotation (rad) of the best rigid fit of current vs reference positions "
        "({}); damage = sum(V phi)/sum(V); fragments: distinct fragment ids of the frame "
        "(connected components of intact bonds, written by pd-solve){}; broken_bonds: half the "
        "sum of the broken_bonds frame field (else exact from /checkpoints bond_alive {} only); "
        "broken_bonds_est = sum(phi_i "
        "deg_i)/2, from damage\n",
        f.name(),
        m.dimension == 2 ? "2D Procrustes angle, unwrapped in time" : "3D Kabsch angle in [0, pi]",
        has.frag ? "" : " (no fragment field in this file: from the checkpoint only)",
        ckpt ? fmt::format("at step {}", ckpt->step) : std::string("(no checkpoint)"));
}

} // namespace

std::size_t write_grains_csv(const h5::File& f, const model::Model& m, const std::string& csv_path,
                             const Progress& progress) {
    store::FrameReader frames(f);
    const std::string particles = store::path::particles;
    const auto n = m.nodes.volume.size();
    const auto nb = m.bodies.node_offsets.size() - 1;
    if (frames.num_nodes() != n)
        throw SchemaError(
            f.name(), particles + "/position/value",
            fmt::format("has {} nodes per frame, expected {} (/nodes)", frames.num_nodes(), n));
    const auto fields = frames.fields();
    const auto field = [&](const char* name) {
        return std::find(fields.begin(), fields.end(), name) != fields.end();
    };
    if (!field("position"))
        throw SchemaError(f.name(), particles + "/position", "missing (no positions)");
    const Has has{field("velocity"), field("damage"), field("fragment"), field("broken_bonds")};
    const Reference ref = reference(m);

    // Exact bond state at the latest checkpoint only.
    const auto ckpt = store::read_latest_checkpoint(f, n, m.bonds.neighbor.size());
    std::optional<BondState> exact;
    if (ckpt)
        exact = bond_state(m, ckpt->alive);

    auto out = open_output(csv_path);
    const std::string note = method_note(f, m, has, ckpt);
    std::string header;
    for (std::size_t c = 0; c < std::size(columns); ++c)
        header += (c ? "," : "") + std::string(columns[c].first);
    fmt::print(out.get(), "{}\n", header);

    std::vector<double> last_angle(nb, 0);
    std::size_t rows = 0;
    std::string line;
    for (std::size_t k = 0; k < frames.num_frames(); ++k) {
        const FrameFields fr = read_frame(f, frames, k, has, n);
        const bool at_ckpt = exact && ckpt->step == frames.step(k);
        for (std::size_t b = 0; b < nb; ++b) {
            GrainRow row;
            row.step = frames.step(k);
            row.time = frames.time(k);
            row.body = b;
            measure(m, ref, fr, has, b, row);
            row.rotation = rotation(m, ref, fr, b, row.com, last_angle[b]);
            bond_counts(m, fr, has, b, at_ckpt ? &*exact : nullptr, row);
            line.clear();
            for (std::size_t c = 0; c < std::size(columns); ++c)
                line += (c ? "," : "") + columns[c].second(row);
            line += '\n';
            if (std::fputs(line.c_str(), out.get()) < 0)
                throw InputError(fmt::format("{}: write failed (disk full?)", csv_path));
            ++rows;
        }
        if (progress)
            progress("grains", k + 1, frames.num_frames());
    }
    if (std::fputs(note.c_str(), out.get()) < 0 || std::fflush(out.get()) != 0)
        throw InputError(fmt::format("{}: write failed (disk full?)", csv_path));
    return rows;
}

} // namespace pd::post

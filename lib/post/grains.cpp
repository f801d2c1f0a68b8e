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
    const auto has = [&](const char* name) {
        return std::find(fields.begin(), fields.end(), name) != fields.end();
    };
    if (!has("position"))
        throw SchemaError(f.name(), particles + "/position", "missing (no positions)");
    const bool has_v = has("velocity"), has_phi = has("damage"), has_frag = has("fragment"),
               has_broken = has("broken_bonds");

    // Reference centres (volume-weighted: the density is uniform within a body).
    std::vector<double> vol(nb, 0), c0(3 * nb, 0);
    for (std::size_t b = 0; b < nb; ++b) {
        for (auto i = m.bodies.node_offsets[b]; i < m.bodies.node_offsets[b + 1]; ++i) {
            vol[b] += m.nodes.volume[i];
            for (int d = 0; d < 3; ++d)
                c0[3 * b + d] += m.nodes.volume[i] * m.nodes.x0[3 * i + d];
        }
        for (int d = 0; d < 3 && vol[b] > 0; ++d)
            c0[3 * b + d] /= vol[b];
    }
    std::vector<std::int64_t> degree(n);
    for (std::size_t i = 0; i < n; ++i)
        degree[i] = m.bonds.offsets[i + 1] - m.bonds.offsets[i];

    // Exact bond state at the latest checkpoint only.
    const auto ckpt = store::read_latest_checkpoint(f, n, m.bonds.neighbor.size());
    std::optional<BondState> exact;
    if (ckpt)
        exact = bond_state(m, ckpt->alive);

    auto out = open_output(csv_path);
    // The method is stated in a comment line after the table: numpy's genfromtxt(names=True)
    // would take a leading comment line for the header.
    const std::string note = fmt::format(
        "# pd-post grains.csv from {}; volume-weighted centre of mass (m) and its velocity "
        "(m s-1); rotation (rad) of the best rigid fit of current vs reference positions "
        "({}); damage = sum(V phi)/sum(V); fragments: distinct fragment ids of the frame "
        "(connected components of intact bonds, written by pd-solve){}; broken_bonds: half the "
        "sum of the broken_bonds frame field (else exact from /checkpoints bond_alive {} only); "
        "broken_bonds_est = sum(phi_i "
        "deg_i)/2, from damage\n",
        f.name(),
        m.dimension == 2 ? "2D Procrustes angle, unwrapped in time" : "3D Kabsch angle in [0, pi]",
        has_frag ? "" : " (no fragment field in this file: from the checkpoint only)",
        ckpt ? fmt::format("at step {}", ckpt->step) : std::string("(no checkpoint)"));
    fmt::print(out.get(), "step,time,body,com_x,com_y,com_z,vcom_x,vcom_y,vcom_z,rotation,"
                          "damage,broken_bonds,fragments,broken_bonds_est\n");

    std::vector<double> last_angle(nb, 0);
    std::size_t rows = 0;
    std::string line;
    for (std::size_t k = 0; k < frames.num_frames(); ++k) {
        const auto x = frames.read("position", k);
        const auto v = has_v ? frames.read("velocity", k) : std::vector<double>{};
        const auto phi = has_phi ? frames.read("damage", k) : std::vector<double>{};
        if (x.size() != 3 * n || (has_v && v.size() != 3 * n) || (has_phi && phi.size() != n))
            throw SchemaError(f.name(), particles,
                              fmt::format("frame {} has a field of the "
                                          "wrong length (n = {})",
                                          k, n));
        const bool at_ckpt = exact && ckpt->step == frames.step(k);
        const auto frag = has_frag ? frames.read("fragment", k) : std::vector<double>{};
        const auto brk = has_broken ? frames.read("broken_bonds", k) : std::vector<double>{};
        for (std::size_t b = 0; b < nb; ++b) {
            const auto lo = m.bodies.node_offsets[b], hi = m.bodies.node_offsets[b + 1];
            double c[3] = {0, 0, 0}, vc[3] = {0, 0, 0}, dmg = 0, est = 0;
            for (auto i = lo; i < hi; ++i) {
                const double w = m.nodes.volume[i];
                for (int d = 0; d < 3; ++d) {
                    c[d] += w * x[3 * i + d];
                    if (has_v)
                        vc[d] += w * v[3 * i + d];
                }
                if (has_phi) {
                    dmg += w * phi[i];
                    est += phi[i] * static_cast<double>(degree[i]);
                }
            }
            const double wb = vol[b] > 0 ? vol[b] : 1.0;
            for (int d = 0; d < 3; ++d) {
                c[d] /= wb;
                vc[d] /= wb;
            }
            // Rigid fit about the centres of mass.
            Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
            for (auto i = lo; i < hi; ++i) {
                const Eigen::Vector3d p(m.nodes.x0[3 * i] - c0[3 * b],
                                        m.nodes.x0[3 * i + 1] - c0[3 * b + 1],
                                        m.nodes.x0[3 * i + 2] - c0[3 * b + 2]);
                const Eigen::Vector3d q(x[3 * i] - c[0], x[3 * i + 1] - c[1], x[3 * i + 2] - c[2]);
                h += m.nodes.volume[i] * p * q.transpose();
            }
            double angle = 0;
            if (m.dimension == 2) {
                angle = std::atan2(h(0, 1) - h(1, 0), h(0, 0) + h(1, 1));
                const double two_pi = 2 * std::numbers::pi;
                angle += two_pi * std::round((last_angle[b] - angle) / two_pi);
                last_angle[b] = angle;
            } else {
                angle = kabsch_angle(h);
            }
            line = fmt::format("{},{:.17g},{},{:.17g},{:.17g},{:.17g},", frames.step(k),
                               frames.time(k), b, c[0], c[1], c[2]);
            line += has_v ? fmt::format("{:.17g},{:.17g},{:.17g},", vc[0], vc[1], vc[2])
                          : std::string(",,,");
            line += fmt::format("{:.17g},", angle);
            line += has_phi ? fmt::format("{:.17g},", dmg / wb) : std::string(",");
            if (has_broken) {
                double nb2 = 0;
                for (auto i = lo; i < hi; ++i)
                    nb2 += brk[static_cast<std::size_t>(i)];
                line += fmt::format("{},", static_cast<std::int64_t>(nb2 / 2));
            } else {
                line += at_ckpt ? fmt::format("{},", exact->broken[b]) : std::string(",");
            }
            if (has_frag) {
                std::vector<double> ids(frag.begin() + lo, frag.begin() + hi);
                std::sort(ids.begin(), ids.end());
                line += fmt::format("{},", std::unique(ids.begin(), ids.end()) - ids.begin());
            } else {
                line += at_ckpt ? fmt::format("{},", exact->fragments[b]) : std::string(",");
            }
            line += has_phi ? fmt::format("{:.17g}\n", est / 2) : std::string("\n");
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

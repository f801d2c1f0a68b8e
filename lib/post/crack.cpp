// SPDX-License-Identifier: MIT
// crack.csv writer (see crack.hpp). One pass over the frames keeps a few numbers per frame
// (tip, angle); the speed is computed from those once every frame has been read.
#include "post/crack.hpp"

#include "core/errors.hpp"
#include "h5/file.hpp"
#include "post/text_out.hpp"
#include "store/frames.hpp"
#include "store/schema.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <vector>

namespace pd::post {

namespace {

struct Tip {
    bool found = false;
    std::size_t count = 0; ///< damaged nodes in the band
    double length = 0;     ///< m along the path
    double x[3] = {0, 0, 0};
    double angle = std::nan(""); ///< rad, principal axis of the damaged nodes, oriented along d
};

/// The tip of frame positions x, damage phi (n nodes): the damaged nodes within opt.band of the
/// path from opt.origin along unit d, their farthest projection and principal axis.
Tip frame_tip(const std::vector<double>& x, const std::vector<double>& phi, std::size_t n,
              const CrackOptions& opt, const double* d) {
    Tip tip;
    double mean[2] = {0, 0}, sxx = 0, syy = 0, sxy = 0;
    for (std::size_t i = 0; i < n; ++i) {
        if (!(phi[i] > opt.threshold))
            continue;
        const double r[3] = {x[3 * i] - opt.origin[0], x[3 * i + 1] - opt.origin[1],
                             x[3 * i + 2] - opt.origin[2]};
        const double s = r[0] * d[0] + r[1] * d[1] + r[2] * d[2];
        const double off =
            std::sqrt(std::max(0.0, r[0] * r[0] + r[1] * r[1] + r[2] * r[2] - s * s));
        if (off > opt.band)
            continue;
        ++tip.count;
        // Welford update of the in-plane (x, y) mean and scatter.
        const double dx = x[3 * i] - mean[0], dy = x[3 * i + 1] - mean[1];
        const double c = static_cast<double>(tip.count);
        mean[0] += dx / c;
        mean[1] += dy / c;
        sxx += dx * (x[3 * i] - mean[0]);
        syy += dy * (x[3 * i + 1] - mean[1]);
        sxy += dx * (x[3 * i + 1] - mean[1]);
        if (!tip.found || s > tip.length) {
            tip.found = true;
            tip.length = s;
            std::copy(x.begin() + 3 * i, x.begin() + 3 * i + 3, tip.x);
        }
    }
    if (tip.count >= 2) {
        double a = 0.5 * std::atan2(2 * sxy, sxx - syy); // principal axis, in (-pi/2, pi/2]
        if (std::cos(a) * d[0] + std::sin(a) * d[1] < 0)
            a += a > 0 ? -std::numbers::pi : std::numbers::pi;
        tip.angle = a;
    }
    return tip;
}

/// The tip of every frame, checking the fields first.
std::vector<Tip> read_tips(const h5::File& f, store::FrameReader& frames, const CrackOptions& opt,
                           const double* d, const Progress& progress) {
    const std::string particles = store::path::particles;
    const auto fields = frames.fields();
    for (const char* name : {"position", "damage"})
        if (std::find(fields.begin(), fields.end(), name) == fields.end())
            throw SchemaError(f.name(), particles + "/" + name,
                              "missing (the crack needs the damage frames; add \"damage\" to "
                              "solver.fields)");
    const auto n = frames.num_nodes(), t = frames.num_frames();
    std::vector<Tip> tips(t);
    for (std::size_t k = 0; k < t; ++k) {
        const auto x = frames.read("position", k);
        const auto phi = frames.read("damage", k);
        if (x.size() != 3 * n || phi.size() != n)
            throw SchemaError(f.name(), particles,
                              fmt::format("frame {} has a field of the wrong "
                                          "length (n = {})",
                                          k, n));
        tips[k] = frame_tip(x, phi, n, opt, d);
        if (progress)
            progress("crack", k + 1, t);
    }
    return tips;
}

/// Local least-squares slope of length(t) over frames [k - w, k + w] that have a tip: the
/// speed column of frame k ("" without a tip or with fewer than 2 points).
std::string local_speed(const std::vector<Tip>& tips, const store::FrameReader& frames,
                        std::size_t k, int w) {
    const std::size_t t = tips.size();
    double st = 0, sl = 0, stt = 0, stl = 0, cnt = 0;
    const auto lo = static_cast<std::size_t>(std::max<long>(0, static_cast<long>(k) - w));
    const auto hi = std::min(t - 1, k + static_cast<std::size_t>(w));
    for (std::size_t j = lo; j <= hi && tips[k].found; ++j) {
        if (!tips[j].found)
            continue;
        const double tj = frames.time(j) - frames.time(k);
        cnt += 1;
        st += tj;
        sl += tips[j].length;
        stt += tj * tj;
        stl += tj * tips[j].length;
    }
    const double den = cnt * stt - st * st;
    return cnt >= 2 && den > 0 ? fmt::format("{:.17g}", (cnt * stl - st * sl) / den)
                               : std::string();
}

} // namespace

std::size_t write_crack_csv(const h5::File& f, const CrackOptions& opt, const std::string& csv_path,
                            const Progress& progress) {
    const double norm = std::hypot(opt.direction[0], opt.direction[1], opt.direction[2]);
    if (!(norm > 0))
        throw InputError("--crack-direction: the direction must not be zero");
    if (opt.half_window < 1)
        throw InputError(fmt::format("--crack-window: {} < 1 frame", opt.half_window));
    const double d[3] = {opt.direction[0] / norm, opt.direction[1] / norm, opt.direction[2] / norm};

    store::FrameReader frames(f);
    const std::vector<Tip> tips = read_tips(f, frames, opt, d, progress);
    const std::size_t t = tips.size();

    auto out = open_output(csv_path);
    fmt::print(out.get(), "step,time,damaged_nodes,tip_length,tip_x,tip_y,tip_z,speed,angle_deg\n");
    const int w = opt.half_window;
    std::string line;
    for (std::size_t k = 0; k < t; ++k) {
        const Tip& tip = tips[k];
        line = fmt::format("{},{:.17g},{},", frames.step(k), frames.time(k), tip.count);
        if (tip.found)
            line += fmt::format("{:.17g},{:.17g},{:.17g},{:.17g},", tip.length, tip.x[0], tip.x[1],
                                tip.x[2]);
        else
            line += ",,,,";
        line += local_speed(tips, frames, k, w) + ",";
        line += std::isnan(tip.angle)
                    ? std::string("\n")
                    : fmt::format("{:.17g}\n", tip.angle * 180 / std::numbers::pi);
        if (std::fputs(line.c_str(), out.get()) < 0)
            throw InputError(fmt::format("{}: write failed (disk full?)", csv_path));
    }
    fmt::print(
        out.get(),
        "# pd-post crack.csv from {}: damaged = phi > {} within {} m of the path from "
        "({:g}, {:g}, {:g}) along ({:g}, {:g}, {:g}) (current positions); tip = the "
        "farthest damaged node along the path; speed (m s-1) = least-squares slope of "
        "tip_length over the {} frames centred on each frame (window half-width {} "
        "frames, truncated at the ends; first-order Savitzky-Golay); angle_deg = principal "
        "axis of the damaged nodes (total least squares), from +x, oriented along the path\n",
        f.name(), opt.threshold, opt.band, opt.origin[0], opt.origin[1], opt.origin[2], d[0], d[1],
        d[2], 2 * w + 1, w);
    if (std::fflush(out.get()) != 0)
        throw InputError(fmt::format("{}: write failed (disk full?)", csv_path));
    return t;
}

} // namespace pd::post

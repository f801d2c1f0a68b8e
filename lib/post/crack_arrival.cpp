// SPDX-License-Identifier: MIT
// Crack arrival times and path fit (see crack_arrival.hpp).
#include "post/crack_arrival.hpp"

#include "core/errors.hpp"
#include "h5/file.hpp"
#include "model/model.hpp"
#include "post/text_out.hpp"
#include "store/frames.hpp"
#include "store/schema.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace pd::post {

ArrivalTracker::ArrivalTracker(std::size_t num_nodes, double threshold)
    : threshold_(threshold)
    , prev_(num_nodes, 0.0)
    , arrival_(num_nodes, std::numeric_limits<double>::quiet_NaN()) {}

void ArrivalTracker::add(double t, std::span<const double> damage) {
    PD_CHECK(damage.size() == arrival_.size(), "ArrivalTracker: damage size");
    for (std::size_t i = 0; i < damage.size(); ++i) {
        if (std::isnan(arrival_[i]) && damage[i] > threshold_) {
            // Linear in time between the previous frame (below) and this one (above).
            if (first_ || !(damage[i] > prev_[i]))
                arrival_[i] = t;
            else
                arrival_[i] =
                    t_prev_ + (threshold_ - prev_[i]) / (damage[i] - prev_[i]) * (t - t_prev_);
        }
        prev_[i] = damage[i];
    }
    first_ = false;
    t_prev_ = t;
}

namespace {

/// Total-least-squares line through the origin of the flagged nodes within `radius` of it (xy),
/// oriented along d; false with fewer than 2 nodes.
bool line_through_origin(std::span<const double> x0, const std::vector<std::uint8_t>& flag,
                         const CrackOptions& opt, const double* d, double radius, double* u) {
    double sxx = 0, syy = 0, sxy = 0;
    std::size_t count = 0;
    for (std::size_t i = 0; i < flag.size(); ++i) {
        if (!flag[i])
            continue;
        const double r[2] = {x0[3 * i] - opt.origin[0], x0[3 * i + 1] - opt.origin[1]};
        if (std::hypot(r[0], r[1]) > radius)
            continue;
        ++count;
        sxx += r[0] * r[0];
        syy += r[1] * r[1];
        sxy += r[0] * r[1];
    }
    if (count < 2)
        return false;
    const double a = 0.5 * std::atan2(2 * sxy, sxx - syy); // principal axis
    u[0] = std::cos(a);
    u[1] = std::sin(a);
    if (u[0] * d[0] + u[1] * d[1] < 0) {
        u[0] = -u[0];
        u[1] = -u[1];
    }
    return true;
}

/// Angle (degrees, [0, 180]) between unit u and axis (xy); NaN for a zero axis.
double angle_to(const double* u, const std::array<double, 3>& axis) {
    const double an = std::hypot(axis[0], axis[1]);
    if (!(an > 0))
        return CrackFit::nan;
    const double c = (u[0] * axis[0] + u[1] * axis[1]) / an;
    return std::acos(std::clamp(c, -1.0, 1.0)) * 180 / std::numbers::pi;
}

/// Selection: arrived, ahead of the origin along unit d (xy), within opt.band of that ray.
void select_ahead(std::span<const double> x0, std::span<const double> arrival,
                  const CrackOptions& opt, const double* d, CrackFit& fit) {
    for (std::size_t i = 0; i < arrival.size(); ++i) {
        if (std::isnan(arrival[i]))
            continue;
        const double r[2] = {x0[3 * i] - opt.origin[0], x0[3 * i + 1] - opt.origin[1]};
        const double s = r[0] * d[0] + r[1] * d[1];
        const double off = std::abs(r[1] * d[0] - r[0] * d[1]);
        if (!(s > 0) || off > opt.band)
            continue;
        fit.on_path[i] = 1;
        ++fit.nodes;
    }
}

/// Keeps the selected nodes linked to the origin: a breadth-first search over them, seeded by
/// those within max(opt.start_radius, opt.link) of the origin (O(m^2) in the m selected nodes).
void keep_linked(std::span<const double> x0, const CrackOptions& opt, CrackFit& fit) {
    std::vector<std::size_t> sel, queue;
    for (std::size_t i = 0; i < fit.on_path.size(); ++i)
        if (fit.on_path[i])
            sel.push_back(i);
    std::vector<std::uint8_t> linked(sel.size(), 0);
    const double l2 = opt.link * opt.link;
    auto dist2 = [&](std::size_t i, const double* p) {
        const double dx = x0[3 * i] - p[0], dy = x0[3 * i + 1] - p[1];
        return dx * dx + dy * dy;
    };
    const double r0 = std::max(opt.start_radius, opt.link);
    for (std::size_t a = 0; a < sel.size(); ++a)
        if (dist2(sel[a], opt.origin.data()) <= r0 * r0) {
            linked[a] = 1;
            queue.push_back(a);
        }
    for (std::size_t q = 0; q < queue.size(); ++q) {
        const double* p = &x0[3 * sel[queue[q]]];
        for (std::size_t a = 0; a < sel.size(); ++a)
            if (!linked[a] && dist2(sel[a], p) <= l2) {
                linked[a] = 1;
                queue.push_back(a);
            }
    }
    fit.nodes = 0;
    for (std::size_t a = 0; a < sel.size(); ++a) {
        if (linked[a])
            ++fit.nodes;
        else
            fit.on_path[sel[a]] = 0;
    }
}

/// Projections of the path nodes on unit u, the first arrival and the farthest node.
void project_path(std::span<const double> x0, std::span<const double> arrival,
                  const CrackOptions& opt, const double* u, CrackFit& fit) {
    for (std::size_t i = 0; i < arrival.size(); ++i) {
        if (!fit.on_path[i])
            continue;
        const double s =
            (x0[3 * i] - opt.origin[0]) * u[0] + (x0[3 * i + 1] - opt.origin[1]) * u[1];
        fit.along[i] = s;
        if (std::isnan(fit.t_start) || arrival[i] < fit.t_start ||
            (arrival[i] == fit.t_start && s < fit.start_length)) {
            fit.t_start = arrival[i];
            fit.start_length = s;
        }
        if (std::isnan(fit.length) || s > fit.length ||
            (s == fit.length && arrival[i] < fit.t_end)) {
            fit.length = s;
            fit.t_end = arrival[i];
        }
    }
    if (fit.t_end > fit.t_start)
        fit.mean_speed = (fit.length - fit.start_length) / (fit.t_end - fit.t_start);
}

/// Largest least-squares slope of the tip history L(t_k) = max projection of the nodes arrived
/// by t_k (frames from t_start) over windows of 2 w + 1 frames; NaN if none.
double peak_speed(std::span<const double> arrival, const CrackFit& fit,
                  std::span<const double> frame_times, std::size_t w) {
    std::vector<double> tk, lk;
    for (double t : frame_times) {
        if (t < fit.t_start)
            continue;
        double L = -std::numeric_limits<double>::infinity();
        for (std::size_t i = 0; i < arrival.size(); ++i)
            if (fit.on_path[i] && arrival[i] <= t)
                L = std::max(L, fit.along[i]);
        tk.push_back(t);
        lk.push_back(L);
    }
    double peak = CrackFit::nan;
    for (std::size_t k = 0; k + 2 * w < tk.size(); ++k) {
        double st = 0, sl = 0, stt = 0, stl = 0;
        const double c = static_cast<double>(2 * w + 1);
        for (std::size_t j = k; j <= k + 2 * w; ++j) {
            const double t = tk[j] - tk[k];
            st += t;
            sl += lk[j];
            stt += t * t;
            stl += t * lk[j];
        }
        const double den = c * stt - st * st;
        if (den > 0) {
            const double v = (c * stl - st * sl) / den;
            if (std::isnan(peak) || v > peak)
                peak = v;
        }
    }
    return peak;
}

} // namespace

CrackFit fit_crack(std::span<const double> x0, std::span<const double> arrival,
                   const CrackOptions& opt, std::span<const double> frame_times) {
    const double dn = std::hypot(opt.direction[0], opt.direction[1]);
    if (!(dn > 0))
        throw InputError("--crack-direction: the direction must have an x or y component");
    const double d[2] = {opt.direction[0] / dn, opt.direction[1] / dn};
    const std::size_t n = arrival.size();
    PD_CHECK(x0.size() == 3 * n, "fit_crack: x0 size");
    CrackFit fit;
    fit.on_path.assign(n, 0);
    fit.along.assign(n, CrackFit::nan);
    select_ahead(x0, arrival, opt, d, fit);
    fit.start_radius = std::max(opt.start_radius, opt.link);
    for (std::size_t i = 0; i < n; ++i)
        if (fit.on_path[i]) {
            const double r = std::hypot(x0[3 * i] - opt.origin[0], x0[3 * i + 1] - opt.origin[1]);
            fit.nearest = std::isnan(fit.nearest) ? r : std::min(fit.nearest, r);
        }
    if (std::isfinite(opt.link) && opt.link > 0)
        keep_linked(x0, opt, fit);
    if (fit.nodes < 2)
        return fit;
    // Direction of the whole path, then the angles (whole path, and nodes within fit_radius).
    double u[2];
    if (!line_through_origin(x0, fit.on_path, opt, d, INFINITY, u))
        return fit;
    fit.direction[0] = u[0];
    fit.direction[1] = u[1];
    fit.path_angle_deg = std::atan2(u[1], u[0]) * 180 / std::numbers::pi;
    fit.path_angle_to_axis_deg = angle_to(u, opt.axis);
    double v[2];
    if (line_through_origin(x0, fit.on_path, opt, d, opt.fit_radius, v)) {
        fit.angle_deg = std::atan2(v[1], v[0]) * 180 / std::numbers::pi;
        fit.angle_to_axis_deg = angle_to(v, opt.axis);
    }
    project_path(x0, arrival, opt, u, fit);
    fit.peak_speed = peak_speed(arrival, fit, frame_times,
                                static_cast<std::size_t>(std::max(1, opt.half_window)));
    return fit;
}

namespace {

std::string num(double v) {
    return std::isnan(v) ? std::string() : fmt::format("{:.10g}", v);
}

} // namespace

CrackFit write_crack_arrivals(const h5::File& f, const model::Model& m, const CrackOptions& opt,
                              const std::string& nodes_csv, const std::string& summary_csv,
                              const Progress& progress) {
    store::FrameReader frames(f);
    const auto fields = frames.fields();
    if (std::find(fields.begin(), fields.end(), "damage") == fields.end())
        throw SchemaError(f.name(), std::string(store::path::particles) + "/damage",
                          "missing (crack arrival times need the damage frames)");
    const auto n = frames.num_nodes(), t = frames.num_frames();
    if (n != m.nodes.num())
        throw SchemaError(f.name(), store::path::particles,
                          fmt::format("frames have {} nodes, the model {}", n, m.nodes.num()));
    CrackOptions o = opt;
    if (o.link == 0)
        for (double h : m.bodies.horizon)
            o.link = std::max(o.link, h);
    ArrivalTracker tracker(n, opt.threshold);
    std::vector<double> times(t);
    for (std::size_t k = 0; k < t; ++k) {
        const auto phi = frames.read("damage", k);
        if (phi.size() != n)
            throw SchemaError(
                f.name(), store::path::particles,
                fmt::format("frame {}: damage has {} values, expected {}", k, phi.size(), n));
        times[k] = frames.time(k);
        tracker.add(times[k], phi);
        if (progress)
            progress("crack arrival", k + 1, t);
    }
    const auto& arrival = tracker.times();
    const CrackFit fit = fit_crack(m.nodes.x0, arrival, o, times);

    auto out = open_output(nodes_csv);
    fmt::print(out.get(), "node,x0,y0,z0,arrival_time,on_path,along\n");
    for (std::size_t i = 0; i < n; ++i) {
        if (std::isnan(arrival[i]))
            continue;
        fmt::print(out.get(), "{},{:.10g},{:.10g},{:.10g},{:.10g},{},{}\n", i, m.nodes.x0[3 * i],
                   m.nodes.x0[3 * i + 1], m.nodes.x0[3 * i + 2], arrival[i], fit.on_path[i],
                   num(fit.along[i]));
    }
    fmt::print(
        out.get(),
        "# pd-post crack_nodes.csv from {}: nodes whose damage exceeded {} (arrival_time "
        "interpolated linearly between frames); on_path = ahead of ({:g}, {:g}) along "
        "({:g}, {:g}), within {} m of that ray and linked to the origin through cracked nodes "
        "at most {} m apart, from those within {} m of it (xy plane, reference positions); "
        "along = projection on the fitted path (m)\n",
        f.name(), opt.threshold, opt.origin[0], opt.origin[1], opt.direction[0], opt.direction[1],
        opt.band, o.link, fit.start_radius);
    if (std::fflush(out.get()) != 0)
        throw InputError(fmt::format("{}: write failed (disk full?)", nodes_csv));

    auto sum = open_output(summary_csv);
    fmt::print(sum.get(), "nodes,angle_deg,angle_to_axis_deg,path_angle_deg,path_angle_to_axis_deg,"
                          "length,start_length,t_start,t_end,mean_speed,peak_speed\n");
    fmt::print(sum.get(), "{},{},{},{},{},{},{},{},{},{},{}\n", fit.nodes, num(fit.angle_deg),
               num(fit.angle_to_axis_deg), num(fit.path_angle_deg), num(fit.path_angle_to_axis_deg),
               num(fit.length), num(fit.start_length), num(fit.t_start), num(fit.t_end),
               num(fit.mean_speed), num(fit.peak_speed));
    fmt::print(
        sum.get(),
        "# pd-post crack_summary.csv from {}: path = nodes of crack_nodes.csv with "
        "on_path = 1; angle_deg = total-least-squares line through the origin ({:g}, {:g}) of "
        "those within {} m of it, from +x; angle_to_axis_deg = its angle to ({:g}, {:g}); "
        "path_angle_* = the same over the whole path; length = farthest "
        "projection (m), t_end its arrival; mean_speed = (length - start_length) / "
        "(t_end - t_start); peak_speed = largest least-squares slope of the tip over {} "
        "frames\n",
        f.name(), opt.origin[0], opt.origin[1], opt.fit_radius, opt.axis[0], opt.axis[1],
        2 * opt.half_window + 1);
    if (std::fflush(sum.get()) != 0)
        throw InputError(fmt::format("{}: write failed (disk full?)", summary_csv));
    return fit;
}

} // namespace pd::post

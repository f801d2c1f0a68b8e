// SPDX-License-Identifier: MIT
// The pd-file validator of `pd-post --check`: walks the entries of the embedded schema JSON and
// reports every violation as "<path>: <problem>", with the same wording as check_pd_file.py.
// Symbols in shapes and ranges (n, nb, B, np, T, To, nmat, nmesh) are resolved from the file.
#include "post/check.hpp"

#include "core/errors.hpp"
#include "h5/file.hpp"
#include "post/check_text.hpp"
#include "post/schema_json.hpp"
#include "store/model_io.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <optional>
#include <regex>
#include <set>

namespace pd::post {

std::string_view schema_json() {
    return detail::schema_json_text;
}

namespace {

using json = nlohmann::json;
constexpr std::uint64_t block_values = std::uint64_t{1} << 22; // values read at once

/// One allowed value of a shape element; `any` for "*".
struct Alt {
    bool any = false;
    double value = 0;
};

using namespace detail;

class Checker {
  public:
    Checker(const h5::File& f, const json& schema)
        : f_(f)
        , schema_(schema) {}

    std::vector<std::string> run() {
        if (!version_ok())
            return out_;
        resolve();
        for (const auto& e : schema_.at("entries")) {
            try {
                check_entry(e);
            } catch (const Error& err) {
                report(e.at("path").get<std::string>(), std::string("cannot check: ") + err.what());
            }
        }
        return out_;
    }

  private:
    void report(const std::string& path, const std::string& msg) {
        out_.push_back(path + ": " + msg);
    }

    // ---- version gate: a newer (or older) MAJOR version is refused before anything else.
    bool version_ok() {
        const std::string want = schema_.at("version");
        const std::string name = schema_.at("schema");
        if (!f_.has_attr("/", "schema")) {
            report("/@schema", "missing (not a pd-file)");
            return false;
        }
        std::string found_name = read_string_attr("/", "schema").value_or("<not a string>");
        if (found_name != name) {
            report("/@schema",
                   fmt::format("is '{}', expected '{}' (not a pd-file)", found_name, name));
            return false;
        }
        auto ver = f_.has_attr("/", "schema_version") ? read_string_attr("/", "schema_version")
                                                      : std::nullopt;
        static const std::regex semver(R"(^(\d+)\.(\d+)\.(\d+)$)");
        std::smatch m;
        if (!ver || !std::regex_match(*ver, m, semver)) {
            report("/@schema_version",
                   fmt::format("is {}, expected MAJOR.MINOR.PATCH",
                               ver ? "'" + *ver + "'" : std::string("missing or not a string")));
            return false;
        }
        int major = std::stoi(m[1].str());
        int want_major = std::stoi(want.substr(0, want.find('.')));
        if (major > want_major) {
            report("/@schema_version",
                   fmt::format("file is pd-file {}, a newer MAJOR version than this checker reads "
                               "({}); refused, use a newer pdgrain",
                               *ver, want));
            return false;
        }
        if (major < want_major) {
            report("/@schema_version",
                   fmt::format("file is pd-file {}, an older MAJOR version than this checker "
                               "reads ({}); refused",
                               *ver, want));
            return false;
        }
        return true;
    }

    /// A scalar string attribute, or nullopt if it holds numbers.
    std::optional<std::string> read_string_attr(const std::string& obj, const std::string& name) {
        try {
            (void)f_.attr_vector<double>(obj, name);
            return std::nullopt;
        } catch (const h5::Error&) {
        }
        return f_.attr_string(obj, name);
    }

    // ---- context: symbols, the tools that ran successfully, the dimension
    void resolve() {
        for (const auto& [name, spec] : schema_.at("symbols").items()) {
            std::optional<double> value;
            if (spec.contains("count")) {
                const std::string g = spec.at("count");
                if (f_.is_group(g))
                    value = static_cast<double>(child_groups(g).size());
            }
            for (const auto& src : spec.value("from", json::array())) {
                const std::string p = src.get<std::string>();
                if (f_.exists(p) && !f_.is_group(p)) {
                    auto sh = f_.shape(p);
                    if (!sh.empty()) {
                        value = static_cast<double>(sh[0]);
                        break;
                    }
                }
            }
            sym_[name] = value;
        }
        ran_ = {"pd-pack", "any"};
        if (f_.is_group("/provenance")) {
            for (const auto& k : child_groups("/provenance")) {
                const std::string g = "/provenance/" + k;
                try {
                    if (f_.has_attr(g, "exit_status") && f_.has_attr(g, "tool") &&
                        f_.attr<std::int32_t>(g, "exit_status") == 0)
                        ran_.insert(read_string_attr(g, "tool").value_or(""));
                } catch (const Error&) {
                }
            }
        }
        try {
            dimension_ = f_.attr<std::int32_t>("/", "dimension");
        } catch (const Error&) {
            dimension_ = 0;
        }
    }

    std::vector<std::string> child_groups(const std::string& g) const {
        std::vector<std::string> out;
        for (const auto& k : f_.list(g))
            if (f_.is_group(join(g, k)))
                out.push_back(k);
        return out;
    }

    static std::string join(const std::string& base, const std::string& name) {
        return (base == "/" ? "" : base) + "/" + name;
    }

    static std::optional<std::string> parent(const std::string& obj) {
        if (obj == "/")
            return std::nullopt;
        auto p = obj.find_last_of('/');
        return p == 0 ? std::string("/") : obj.substr(0, p);
    }

    /// Concrete object paths matching `pattern` ("*" = any existing child group).
    std::vector<std::string> expand(const std::string& pattern) const {
        std::vector<std::string> paths{"/"};
        for (const auto& part : split(pattern, '/')) {
            if (part.empty())
                continue;
            std::vector<std::string> next;
            for (const auto& base : paths) {
                if (part == "*") {
                    if (f_.is_group(base))
                        for (const auto& k : child_groups(base))
                            next.push_back(join(base, k));
                } else {
                    next.push_back(join(base, part));
                }
            }
            paths = std::move(next);
        }
        return paths;
    }

    bool required(const json& e) const {
        return e.value("required", false) && ran_.count(e.value("written_by", "")) > 0;
    }

    // ---- expressions: 3, "*", "n", "nb+1", "n-1"; alternatives "nb|n"
    std::optional<double> eval_term(const json& t) const {
        if (t.is_number())
            return t.get<double>();
        static const std::regex rx(R"(^([A-Za-z_]\w*)?\s*(?:([+-])?\s*(\d+))?$)");
        const std::string s = trim(t.get<std::string>());
        std::smatch m;
        if (!std::regex_match(s, m, rx) || (!m[1].matched && !m[3].matched))
            throw InternalError(fmt::format("bad expression '{}' in the embedded schema", s));
        double v = 0;
        if (m[1].matched) {
            auto it = sym_.find(m[1].str());
            if (it == sym_.end() || !it->second)
                return std::nullopt;
            v = *it->second;
        }
        if (m[3].matched)
            v += (m[2].matched && m[2].str() == "-" ? -1.0 : 1.0) * std::stod(m[3].str());
        return v;
    }

    std::optional<std::vector<Alt>> alternatives(const json& expr) const {
        if (expr.is_number())
            return std::vector<Alt>{{false, expr.get<double>()}};
        std::vector<Alt> out;
        for (const auto& t : split(expr.get<std::string>(), '|')) {
            if (trim(t) == "*") {
                out.push_back({true, 0});
                continue;
            }
            auto v = eval_term(json(t));
            if (!v)
                return std::nullopt;
            out.push_back({false, *v});
        }
        return out;
    }

    void check_shape(const json& e, const std::string& shown, const h5::dims_t& shape) {
        const json& expected = e.at("shape");
        std::vector<std::string> found, exp, resolved;
        for (auto d : shape)
            found.push_back(std::to_string(d));
        for (const auto& x : expected)
            exp.push_back(json_item_text(x));
        bool ok = shape.size() == expected.size();
        bool unresolved = false;
        for (std::size_t i = 0; ok && i < shape.size(); ++i) {
            auto alts = alternatives(expected[i]);
            if (!alts) {
                unresolved = true;
                break;
            }
            std::string text;
            bool hit = false;
            for (const auto& a : *alts) {
                if (!text.empty())
                    text += '|';
                text += a.any ? std::string("*") : num_text(a.value);
                hit = hit || a.any || static_cast<double>(shape[i]) == a.value;
            }
            resolved.push_back(text);
            ok = hit;
        }
        if (ok || unresolved)
            return;
        std::string msg = "shape " + tuple_text(found) + " expected " + tuple_text(exp);
        if (resolved.size() == exp.size() && resolved != exp)
            msg += "=" + tuple_text(resolved);
        report(shown, msg);
    }

    void check_range(const json& e, const std::string& shown, double lo_found, double hi_found) {
        const json& r = e.at("range");
        auto bound = [&](const json& b) { return b.is_null() ? std::nullopt : eval_term(b); };
        auto lo = bound(r[0]);
        auto hi = bound(r[1]);
        if ((lo && lo_found < *lo) || (hi && hi_found > *hi)) {
            auto show = [](const json& b, const std::optional<double>& v) -> std::string {
                if (b.is_null())
                    return "inf";
                if (!v)
                    return json_item_text(b);
                if (b.is_number() || json_item_text(b) == num_text(*v))
                    return num_text(*v);
                return json_item_text(b) + "=" + num_text(*v);
            };
            report(shown,
                   fmt::format("values in [{}, {}], expected within [{}, {}]", num_text(lo_found),
                               num_text(hi_found), show(r[0], lo), show(r[1], hi)));
        }
    }

    /// value / enum / pattern / range checks of a scalar (or small vector) value.
    void check_value(const json& e, const std::string& shown, const json& v) {
        auto equal = [](const json& a, const json& b) {
            if (a.is_number() && b.is_number())
                return a.get<double>() == b.get<double>();
            if (a.is_array() && b.is_array() && a.size() == b.size()) {
                for (std::size_t i = 0; i < a.size(); ++i)
                    if (!(a[i].is_number() && b[i].is_number()
                              ? a[i].get<double>() == b[i].get<double>()
                              : a[i] == b[i]))
                        return false;
                return true;
            }
            return a == b;
        };
        if (e.contains("value") && !equal(v, e.at("value")))
            report(shown,
                   fmt::format("is {}, expected {}", value_text(v), value_text(e.at("value"))));
        if (e.contains("enum")) {
            const auto& en = e.at("enum");
            if (std::none_of(en.begin(), en.end(), [&](const json& x) { return equal(v, x); }))
                report(shown,
                       fmt::format("is {}, expected one of {}", value_text(v), json_text(en)));
        }
        if (e.contains("pattern")) {
            const std::regex rx(e.at("pattern").get<std::string>());
            if (!v.is_string() || !std::regex_search(v.get<std::string>(), rx))
                report(shown, fmt::format("is {}, does not match {}", value_text(v),
                                          e.at("pattern").get<std::string>()));
        }
        if (e.contains("range") && v.is_number())
            check_range(e, shown, v.get<double>(), v.get<double>());
    }

    void check_type(const json& e, const std::string& shown, char cls, std::size_t size) {
        if (!e.contains("dtype"))
            return;
        const std::string want_cls = e.at("dtype");
        const bool sized = e.contains("size") && want_cls != "string";
        const std::string want =
            want_cls + (sized ? std::to_string(8 * e.at("size").get<int>()) : std::string{});
        const std::string found =
            cls == 's' ? std::string("string") : class_name(cls) + std::to_string(8 * size);
        if (class_name(cls) != want_cls || (sized && size != e.at("size").get<std::size_t>()))
            report(shown, fmt::format("dtype {}, expected {}", found, want));
    }

    // ---- entries
    void check_entry(const json& e) {
        const std::string path = e.at("path");
        const auto at = path.find('@');
        std::string obj = at == std::string::npos ? path : path.substr(0, at);
        if (obj.empty())
            obj = "/";
        if (e.at("kind") == "group" && obj.size() >= 2 && obj.ends_with("/*"))
            check_pattern_group(e, obj);
        for (const auto& o : expand(obj)) {
            if (at != std::string::npos)
                check_attribute(e, o, path.substr(at + 1));
            else
                check_object(e, o);
        }
    }

    void check_pattern_group(const json& e, const std::string& pattern) {
        std::string par = pattern.substr(0, pattern.size() - 2);
        if (par.empty())
            par = "/";
        for (const auto& base : expand(par)) {
            if (!f_.is_group(base))
                continue;
            auto names = child_groups(base);
            const auto min_count = e.value("min_count", 0);
            if (required(e) && static_cast<int>(names.size()) < min_count)
                report(base, fmt::format("holds {} groups, expected at least {}", names.size(),
                                         min_count));
            if (e.contains("name_pattern")) {
                const std::regex rx(e.at("name_pattern").get<std::string>());
                for (const auto& k : names)
                    if (!std::regex_search(k, rx))
                        report(join(base, k),
                               "name does not match " + e.at("name_pattern").get<std::string>());
            }
        }
    }

    void check_object(const json& e, const std::string& path) {
        const std::string kind = e.at("kind");
        if (!f_.exists(path)) {
            auto par = parent(path);
            if (required(e) && (!par || f_.is_group(*par)))
                report(path, "missing");
            return;
        }
        const bool is_group = f_.is_group(path);
        if (is_group != (kind == "group")) {
            report(path,
                   fmt::format("is a {}, expected a {}", is_group ? "group" : "dataset", kind));
            return;
        }
        if (is_group)
            return;
        const char cls = f_.type_class(path);
        check_type(e, path, cls, f_.type_size(path));
        const auto shape = f_.shape(path);
        if (e.contains("shape"))
            check_shape(e, path, shape);
        if (e.contains("unit") && !e.at("unit").is_null()) {
            const std::string want = e.at("unit");
            if (!f_.has_attr(path, "unit")) {
                report(path, fmt::format("missing unit attribute (expected '{}')", want));
            } else {
                auto unit = read_string_attr(path, "unit");
                if (!unit)
                    report(path,
                           fmt::format("unit attribute is not a string (expected '{}')", want));
                else if (!is_one_of(*unit, want))
                    report(path, fmt::format("unit '{}', expected '{}'", *unit, want));
            }
        }
        check_values(e, path, shape, cls);
    }

    void check_attribute(const json& e, const std::string& obj, const std::string& name) {
        const std::string shown = (obj == "/" ? std::string("/") : obj) + "@" + name;
        if (!f_.exists(obj))
            return; // the object's own entry reports it
        if (!f_.has_attr(obj, name)) {
            if (required(e))
                report(shown, "missing");
            return;
        }
        const std::string want = e.value("dtype", "");
        std::vector<double> nums;
        bool is_string = false;
        try {
            nums = f_.attr_vector<double>(obj, name);
        } catch (const h5::Error&) {
            is_string = true;
        }
        if (is_string != (want == "string")) {
            report(shown, fmt::format("dtype {}, expected {}", is_string ? "string" : "number",
                                      want + (want != "string" && e.contains("size")
                                                  ? std::to_string(8 * e.at("size").get<int>())
                                                  : std::string{})));
            return;
        }
        std::size_t expect_count = 1;
        for (const auto& d : e.value("shape", json::array()))
            expect_count *= d.is_number() ? d.get<std::size_t>() : 0;
        if (is_string) {
            // The h5 layer reads scalar string attributes only; string arrays get a presence check.
            if (e.value("rank", 0) == 0)
                check_value(e, shown, json(f_.attr_string(obj, name)));
            return;
        }
        if (nums.size() != expect_count) {
            report(shown, fmt::format("has {} values, expected shape {}", nums.size(),
                                      e.value("shape", json::array()).dump()));
            return;
        }
        check_value(e, shown, e.value("rank", 0) == 0 ? json(nums[0]) : json(nums));
    }

    void check_values(const json& e, const std::string& path, const h5::dims_t& shape, char cls) {
        if (cls == 's') {
            if ((e.contains("value") || e.contains("enum") || e.contains("pattern")) &&
                shape.empty())
                check_value(e, path, json(f_.read_string(path)));
            return;
        }
        if (cls != 'f' && cls != 'i' && cls != 'u')
            return;
        const bool finite = cls == 'f' && e.value("finite", true);
        const bool planar =
            e.value("planar_z", false) && dimension_ == 2 && !shape.empty() && shape.back() == 3;
        const bool range = e.contains("range");
        const bool csr = e.contains("csr");
        const bool scalar_value = shape.empty() && (e.contains("value") || e.contains("enum"));
        if (!(finite || planar || range || csr || scalar_value))
            return;
        std::uint64_t total = 1;
        for (auto d : shape)
            total *= d;
        if (total == 0)
            return;
        std::uint64_t bad = 0;
        double lo = INFINITY, hi = -INFINITY, zmax = 0;
        auto scan = [&](const std::vector<double>& a) {
            for (std::size_t i = 0; i < a.size(); ++i) {
                const double x = a[i];
                if (!std::isfinite(x)) {
                    ++bad;
                    continue;
                }
                lo = std::min(lo, x);
                hi = std::max(hi, x);
                if (planar && i % 3 == 2)
                    zmax = std::max(zmax, std::fabs(x));
            }
        };
        f_.check_storage(path); // a huge declared, never-written dataset: not scanned
        if (shape.empty()) {
            scan(f_.read<double>(path));
        } else {
            const std::uint64_t row = std::max<std::uint64_t>(1, total / shape[0]);
            const std::uint64_t step = std::max<std::uint64_t>(1, block_values / row);
            for (std::uint64_t r = 0; r < shape[0]; r += step)
                scan(f_.read_rows<double>(path, r, std::min(step, shape[0] - r)));
        }
        if (bad && finite)
            report(path, fmt::format("{} non-finite values (NaN or inf)", bad));
        if (planar && zmax != 0)
            report(path, fmt::format("z component is not 0 in a 2D file (max |z| = {:g})", zmax));
        if (range && lo <= hi)
            check_range(e, path, lo, hi);
        if (scalar_value) {
            json v = f_.read<double>(path).at(0);
            json ev = e;
            ev.erase("range");
            check_value(ev, path, v);
        }
        if (csr)
            check_csr(path, e.at("csr").get<std::string>());
    }

    void check_csr(const std::string& path, const std::string& total_sym) {
        const auto off = f_.read<std::int64_t>(path);
        if (off.empty())
            return;
        if (off[0] != 0)
            report(path, fmt::format("first offset is {}, expected 0", off[0]));
        for (std::size_t i = 0; i + 1 < off.size(); ++i) {
            if (off[i + 1] < off[i]) {
                report(path,
                       fmt::format("offsets decrease at row {} ({} > {})", i, off[i], off[i + 1]));
                break;
            }
        }
        auto it = sym_.find(total_sym);
        if (it != sym_.end() && it->second && static_cast<double>(off.back()) != *it->second)
            report(path, fmt::format("last offset is {}, expected {}={}", off.back(), total_sym,
                                     num_text(*it->second)));
    }

    const h5::File& f_;
    const json& schema_;
    std::vector<std::string> out_;
    std::map<std::string, std::optional<double>> sym_;
    std::set<std::string> ran_;
    int dimension_ = 0;
};

} // namespace

std::vector<std::string> check(const h5::File& f) {
    json schema;
    try {
        schema = json::parse(schema_json());
    } catch (const json::exception& e) {
        throw InternalError(std::string("embedded pd-file schema does not parse: ") + e.what());
    }
    auto problems = Checker(f, schema).run();
    if (problems.empty()) {
        // What the schema cannot say (cross-dataset consistency, physical ranges): the checks
        // every tool makes when it reads the model.
        try {
            (void)store::read_model(f);
        } catch (const SchemaError& e) {
            std::string what = e.what();
            if (what.rfind(f.name() + ": ", 0) == 0)
                what = what.substr(f.name().size() + 2);
            problems.push_back(what);
        }
    }
    return problems;
}

} // namespace pd::post

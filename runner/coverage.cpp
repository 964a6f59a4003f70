#include "runner/coverage.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "core/nearest.h"
#include "core/pipeline.h"
#include "runner/json_read.h"

namespace hdrc {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

double effective_value(const Case& c, const std::string& name) {
  // A pipeline with cvars (UE's) reads them; a case's settings are its pipeline's.
  if (c.stage && !pipeline_of(*c.stage).cvars().empty() && find_cvar(name))
    return c.cvars.get(name);
  return c.settings.get(name);
}

std::string coverage_file_name(const Pipeline& pipeline, const std::string& suite) {
  if (&pipeline == &default_pipeline())
    return suite == "exhaustive" ? "coverage_exhaustive.json" : "coverage.json";
  return "coverage_" + std::string(pipeline.name) + ".json";
}

namespace {

std::string fmt(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

std::string show(const json& v) {
  std::string s = v.dump();
  return s.size() > 60 ? s.substr(0, 57) + "..." : s;
}

const CvarInfo* pipeline_cvar(const Pipeline& p, const std::string& n) {
  for (const auto& c : p.cvars())
    if (c.name == n) return &c;
  return nullptr;
}

bool known_name(const Pipeline& p, const std::string& n) {
  if (pipeline_cvar(p, n)) return true;
  const SettingInfo* s = find_setting(p.settings(), n);
  return s && s->components == 1;
}

std::vector<std::string> all_names(const Pipeline& p) {
  std::vector<std::string> names;
  for (const auto& c : p.cvars()) names.emplace_back(c.name);
  for (const auto& s : p.settings())
    if (s.components == 1) names.emplace_back(s.name);
  return names;
}

// The declared values of `name` that the stages can hold (output devices: those of the stages).
std::vector<double> domain(const CoverageSpec& spec, const std::string& name,
                           const std::vector<std::string>& stages) {
  std::vector<double> values =
      spec.values.count(name) ? spec.values.at(name) : std::vector<double>{};
  if (name != "r.HDR.Display.OutputDevice") return values;
  std::set<int> devices;
  for (const auto& s : stages)
    if (const StageInfo* info = find_stage(s))
      devices.insert(info->devices.begin(), info->devices.end());
  std::vector<double> out;
  for (double v : values)
    if (devices.count(static_cast<int>(v))) out.push_back(v);
  return out;
}

}  // namespace

CoverageSpec load_coverage_spec(const std::string& cases_dir, std::vector<Error>* errors,
                                const std::string& file_name, const Pipeline* pipeline) {
  CoverageSpec spec;
  spec.pipeline = pipeline ? pipeline : &default_pipeline();
  const Pipeline& pl = *spec.pipeline;
  const fs::path path = fs::path(cases_dir) / file_name;
  spec.file = path.generic_string();
  auto fail = [&](const std::string& ptr, const std::string& msg, const std::string& choices = "") {
    errors->push_back(Error{spec.file, ptr, msg, choices});
  };
  if (!fs::exists(path)) {
    fail("", "no coverage declaration: the suite must declare what it covers",
         "a coverage.json beside the case files (docs/cases.md)");
    return spec;
  }
  auto parsed = read_json_file<json>(spec.file, "coverage file");
  if (!parsed) {
    errors->push_back(parsed.error());
    return spec;
  }
  json doc = std::move(*parsed);
  const std::vector<std::string> names = all_names(pl);
  auto name_ok = [&](const json& n, const std::string& ptr) {
    if (n.is_string() && known_name(pl, n.get<std::string>())) return true;
    std::string near;
    if (n.is_string())
      for (const auto& s : nearest_names(n.get<std::string>(), names, 3))
        near += (near.empty() ? "" : ", ") + s;
    fail(ptr, "unknown cvar or scalar setting " + show(n), "nearest: " + near);
    return false;
  };
  if (!doc.is_object()) {
    fail("", "the coverage file is a JSON object");
    return spec;
  }
  for (auto it = doc.begin(); it != doc.end(); ++it)
    if (it.key() != "$schema" && it.key() != "description" && it.key() != "values" &&
        it.key() != "requirements")
      fail("/" + it.key(), "unknown key '" + it.key() + "'",
           "$schema, description, values, requirements");
  if (!doc.contains("values") || !doc["values"].is_object()) {
    fail("/values", "expected an object of name: [declared values]");
  } else {
    for (auto it = doc["values"].begin(); it != doc["values"].end(); ++it) {
      const std::string ptr = "/values/" + it.key();
      if (!name_ok(json(it.key()), ptr)) continue;
      if (!it.value().is_array() || it.value().empty()) {
        fail(ptr, "expected a non-empty array of values, got " + show(it.value()));
        continue;
      }
      std::vector<double> values;
      for (size_t i = 0; i < it.value().size(); ++i) {
        const json& v = it.value()[i];
        double lo = 0, hi = 0;
        if (const CvarInfo* c = pipeline_cvar(pl, it.key())) {
          lo = c->min_value;
          hi = c->max_value;
        } else {
          const SettingInfo* s = find_setting(pl.settings(), it.key());
          lo = s->min_value;
          hi = s->max_value;
        }
        if (!v.is_number() || !(v.get<double>() >= lo && v.get<double>() <= hi)) {
          fail(ptr + "/" + std::to_string(i), "declared value " + show(v) + " is not valid",
               fmt(lo) + " to " + fmt(hi));
          continue;
        }
        values.push_back(v.get<double>());
      }
      spec.values[it.key()] = values;
      spec.order.push_back(it.key());
    }
  }
  if (!doc.contains("requirements") || !doc["requirements"].is_array()) {
    fail("/requirements", "expected an array of requirements");
    return spec;
  }
  for (size_t i = 0; i < doc["requirements"].size(); ++i) {
    const json& r = doc["requirements"][i];
    const std::string ptr = "/requirements/" + std::to_string(i);
    if (!r.is_object()) {
      fail(ptr, "expected an object");
      continue;
    }
    CoverageRequirement req;
    for (auto it = r.begin(); it != r.end(); ++it)
      if (it.key() != "name" && it.key() != "stages" && it.key() != "full" && it.key() != "of" &&
          it.key() != "with")
        fail(ptr + "/" + it.key(), "unknown key '" + it.key() + "'",
             "name, stages, full, of, with");
    if (r.contains("name") && r["name"].is_string()) req.name = r["name"].get<std::string>();
    if (req.name.empty())
      fail(ptr + "/name",
           "a requirement needs a name" + (r.contains("name") ? ", got " + show(r["name"]) : ""),
           "a non-empty string");
    if (!r.contains("stages") || !r["stages"].is_array() || r["stages"].empty()) {
      fail(ptr + "/stages", "expected a non-empty array of stages", stage_names(pl));
    } else {
      for (size_t k = 0; k < r["stages"].size(); ++k) {
        const json& s = r["stages"][k];
        if (!s.is_string() || !find_stage(pl, s.get<std::string>()))
          fail(ptr + "/stages/" + std::to_string(k), "unknown stage " + show(s), stage_names(pl));
        else
          req.stages.push_back(s.get<std::string>());
      }
    }
    const bool full = r.contains("full");
    if (full == (r.contains("of") || r.contains("with")) ||
        (!full && !(r.contains("of") && r.contains("with"))))
      fail(ptr, "a requirement has either \"full\" or both \"of\" and \"with\"", "full; of + with");
    for (const char* key : {"full", "of", "with"}) {
      if (!r.contains(key)) continue;
      if (!r[key].is_array() || r[key].empty()) {
        fail(ptr + "/" + key, "expected a non-empty array of names");
        continue;
      }
      auto& dst = std::string(key) == "full" ? req.full
                  : std::string(key) == "of" ? req.of
                                             : req.with;
      for (size_t k = 0; k < r[key].size(); ++k) {
        const std::string kp = ptr + "/" + key + "/" + std::to_string(k);
        if (!name_ok(r[key][k], kp)) continue;
        const std::string n = r[key][k].get<std::string>();
        if (!spec.values.count(n)) {
          fail(kp, n + " has no declared values", "declare them under /values");
          continue;
        }
        dst.push_back(n);
      }
    }
    spec.requirements.push_back(req);
  }
  return spec;
}

size_t CoverageReport::values_declared() const {
  size_t n = 0;
  for (const auto& c : names) n += c.values.size();
  return n;
}
size_t CoverageReport::values_covered() const {
  size_t n = 0;
  for (const auto& c : names)
    for (const auto& v : c.values) n += v.cases > 0;
  return n;
}
size_t CoverageReport::combinations() const {
  size_t n = 0;
  for (const auto& r : requirements) n += r.combinations;
  return n;
}
size_t CoverageReport::combinations_covered() const {
  size_t n = 0;
  for (const auto& r : requirements) n += r.covered;
  return n;
}

CoverageReport compute_coverage(const CoverageSpec& spec, const std::vector<Case>& all_cases) {
  CoverageReport report;
  // The declaring pipeline's cases only: another pipeline's settings are not these.
  const Pipeline& pipeline = spec.pipeline ? *spec.pipeline : default_pipeline();
  std::vector<Case> cases;
  for (const Case& c : all_cases)
    if (c.stage && &pipeline_of(*c.stage) == &pipeline) cases.push_back(c);
  // Why each case is degenerate ("" when it is not), as the runner will report it.
  std::vector<std::string> degenerate(cases.size());
  for (size_t i = 0; i < cases.size(); ++i) {
    auto r = pipeline.resolve(cases[i], std::max(cases[i].input.width, 1),
                              std::max(cases[i].input.height, 1));
    if (r) degenerate[i] = r->degenerate;
  }
  auto in_stages = [](const Case& c, const std::vector<std::string>& stages) {
    return std::find(stages.begin(), stages.end(), std::string(c.stage->name)) != stages.end();
  };

  for (const std::string& name : spec.order) {
    NameCoverage nc;
    nc.name = name;
    for (const auto& r : spec.requirements) {
      const bool uses = std::count(r.full.begin(), r.full.end(), name) ||
                        std::count(r.of.begin(), r.of.end(), name) ||
                        std::count(r.with.begin(), r.with.end(), name);
      if (!uses) continue;
      for (const auto& s : r.stages)
        if (std::find(nc.stages.begin(), nc.stages.end(), s) == nc.stages.end())
          nc.stages.push_back(s);
    }
    const bool any_stage = nc.stages.empty();
    std::vector<double> values = any_stage ? spec.values.at(name) : domain(spec, name, nc.stages);
    for (double v : values) {
      ValueCoverage vc{v};
      for (size_t i = 0; i < cases.size(); ++i) {
        if (!any_stage && !in_stages(cases[i], nc.stages)) continue;
        if (effective_value(cases[i], name) != v) continue;
        ++vc.cases;
        vc.degenerate += !degenerate[i].empty();
      }
      nc.values.push_back(vc);
    }
    report.names.push_back(nc);
  }

  for (const auto& req : spec.requirements) {
    RequirementCoverage rc;
    rc.requirement = req;
    // The groups of dimensions whose value combinations are required.
    std::vector<std::vector<std::string>> groups;
    if (!req.full.empty()) {
      groups.push_back(req.full);
    } else {
      std::set<std::pair<std::string, std::string>> seen;
      for (const auto& a : req.of)
        for (const auto& b : req.with) {
          if (a == b) continue;
          const auto key = a < b ? std::pair{a, b} : std::pair{b, a};
          if (seen.insert(key).second) groups.push_back({a, b});
        }
    }
    for (const auto& dims : groups) {
      std::vector<std::vector<double>> doms;
      for (const auto& d : dims) doms.push_back(domain(spec, d, req.stages));
      // covered tuple -> reason when only degenerate cases hold it ("" when a live case does).
      std::map<std::vector<double>, std::string> held;
      for (size_t i = 0; i < cases.size(); ++i) {
        if (!in_stages(cases[i], req.stages)) continue;
        std::vector<double> t;
        for (const auto& d : dims) t.push_back(effective_value(cases[i], d));
        auto it = held.find(t);
        if (it == held.end())
          held[t] = degenerate[i];
        else if (degenerate[i].empty())
          it->second.clear();
      }
      size_t total = 1;
      for (const auto& d : doms) total *= d.size();
      for (size_t k = 0; k < total; ++k) {
        std::vector<double> t(dims.size());
        size_t rest = k;
        for (size_t d = dims.size(); d-- > 0;) {
          t[d] = doms[d][rest % doms[d].size()];
          rest /= doms[d].size();
        }
        std::string label;
        for (size_t d = 0; d < dims.size(); ++d)
          label += (d ? ", " : "") + dims[d] + "=" + fmt(t[d]);
        ++rc.combinations;
        auto it = held.find(t);
        if (it == held.end()) {
          rc.missing.push_back(label);
          continue;
        }
        ++rc.covered;
        if (!it->second.empty()) rc.degenerate.push_back(label + ": " + it->second);
      }
    }
    report.requirements.push_back(rc);
  }
  return report;
}

std::string CoverageReport::text() const {
  std::ostringstream out;
  char line[512];
  out << "Declared values (cases that run with each; d = of them DEGENERATE):\n";
  for (const auto& n : names) {
    std::string stages;
    for (const auto& s : n.stages) stages += (stages.empty() ? "" : ",") + s;
    std::snprintf(line, sizeof line, "  %-42s %-26s", n.name.c_str(),
                  stages.empty() ? "any stage" : stages.c_str());
    out << line;
    for (const auto& v : n.values) {
      out << " " << fmt(v.value) << ":";
      if (v.cases == 0)
        out << "UNCOVERED";
      else
        out << v.cases
            << (v.degenerate ? std::string("(") + std::to_string(v.degenerate) + "d)" : "");
    }
    out << "\n";
  }
  out << "\nRequired combinations:\n";
  for (const auto& r : requirements) {
    size_t deg = r.degenerate.size();
    std::snprintf(line, sizeof line, "  %-86s %5zu/%-5zu%s\n", r.requirement.name.c_str(),
                  r.covered, r.combinations,
                  deg ? (" (" + std::to_string(deg) + " only degenerate)").c_str() : "");
    out << line;
  }
  bool any_deg = false;
  for (const auto& r : requirements) any_deg |= !r.degenerate.empty();
  if (any_deg) {
    out << "\nCombinations held only by DEGENERATE cases (UE computes degenerate parameters; "
           "reported as DEGENERATE, never as passes):\n";
    for (const auto& r : requirements)
      for (const auto& d : r.degenerate) out << "  " << r.requirement.name << ": " << d << "\n";
  }
  bool any_missing = false;
  for (const auto& n : names)
    for (const auto& v : n.values)
      if (v.cases == 0) {
        if (!any_missing) out << "\nUNCOVERED:\n";
        any_missing = true;
        out << "  value " << n.name << "=" << fmt(v.value) << "\n";
      }
  for (const auto& r : requirements)
    for (const auto& m : r.missing) {
      if (!any_missing) out << "\nUNCOVERED:\n";
      any_missing = true;
      out << "  " << r.requirement.name << ": " << m << "\n";
    }
  const double vp = values_declared() ? 100.0 * values_covered() / values_declared() : 100.0;
  const double cp = combinations() ? 100.0 * combinations_covered() / combinations() : 100.0;
  std::snprintf(
      line, sizeof line, "\ncoverage: values %zu/%zu (%.1f %%), combinations %zu/%zu (%.1f %%)\n",
      values_covered(), values_declared(), vp, combinations_covered(), combinations(), cp);
  out << line;
  return out.str();
}

}  // namespace hdrc

#include "app/sweep.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <ostream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "app/expression.hpp"
#include "io/atomic_file.hpp"
#include "io/output_dir.hpp"
#include "io/run.hpp"
#include "io/scene.hpp"

namespace sphib::app {

namespace {

namespace fs = std::filesystem;

std::pair<std::string, std::string> split_kv(const std::string& kv, const char* option) {
  const auto eq = kv.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == kv.size())
    throw UsageError(std::string(option) + " " + kv + ": expected key=value");
  return {kv.substr(0, eq), kv.substr(eq + 1)};
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, sep))
    if (!item.empty()) out.push_back(item);
  return out;
}

// A JSON value as a table cell: numbers as Python prints them, strings bare, null empty.
std::string cell(const nlohmann::json& v, bool markdown) {
  if (v.is_null()) return "";
  if (v.is_string()) {
    std::string t = v.get<std::string>();
    if (markdown)  // a '|' inside a Markdown table cell
      for (size_t k = t.find('|'); k != std::string::npos; k = t.find('|', k + 2)) t.replace(k, 1, "\\|");
    return t;
  }
  if (v.is_boolean()) return v.get<bool>() ? "true" : "false";
  if (v.is_number_integer() || v.is_number_unsigned()) return v.dump();
  if (v.is_number_float()) {
    if (!markdown) return format_number({v.get<double>(), false});
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.4g", v.get<double>());
    return buf;
  }
  return v.dump();
}

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

bool as_number(const nlohmann::json& v, double& x) {
  if (v.is_number()) { x = v.get<double>(); return true; }
  if (!v.is_string()) return false;
  const std::string s = v.get<std::string>();
  char* end = nullptr;
  x = std::strtod(s.c_str(), &end);
  return end && *end == '\0' && end != s.c_str();
}

// One run of the sweep: its varied and derived values, the overrides and the scene they give.
struct Run {
  std::map<std::string, std::string> env;  // varied and derived values as set
  std::vector<std::string> sets;
  Scene scene;
  std::string dir;
};

// The varied keys with their values, the derived keys with their expressions.
struct Plan {
  std::vector<std::string> keys;
  std::vector<std::vector<std::string>> values;
  std::vector<std::pair<std::string, std::string>> derives;
};

Plan parse_plan(const SweepOptions& o) {
  Plan p;
  for (const auto& v : o.vary) {
    auto [k, list] = split_kv(v, "--vary");
    p.keys.push_back(k);
    p.values.push_back(split(list, ','));
    if (p.values.back().empty()) throw UsageError("--vary " + v + ": no values");
  }
  if (p.keys.empty()) throw UsageError("give at least one --vary key=v1,v2,...");
  auto varied = [&](const std::string& k) { return std::find(p.keys.begin(), p.keys.end(), k) != p.keys.end(); };
  for (size_t k = 0; k < p.keys.size(); ++k)
    if (std::find(p.keys.begin(), p.keys.begin() + k, p.keys[k]) != p.keys.begin() + k)
      throw UsageError("--vary " + p.keys[k] + ": the key is varied twice (give all its values in one --vary)");
  for (const auto& d : o.derive) {
    p.derives.push_back(split_kv(d, "--derive"));
    if (varied(p.derives.back().first))
      throw UsageError("--derive " + p.derives.back().first + ": the key is varied (--vary " + p.derives.back().first +
                       "); a key is either varied or derived");
  }
  for (const auto& s : o.set) {
    const std::string k = split_kv(s, "--set").first;
    if (varied(k))
      throw UsageError("--set " + k + ": the key is varied (--vary " + k + "): its value would replace every varied one; "
                       "give its values in --vary only");
    for (const auto& [dk, e] : p.derives)
      if (dk == k) throw UsageError("--set " + k + ": the key is derived (--derive " + k + "); give it in one of the two");
  }
  if (o.report.empty()) throw UsageError("give the summary fields to tabulate: --report a,b");
  return p;
}

// Every combination, the last key fastest (itertools.product), set up before anything runs
// (SceneError: refused before anything runs).
std::vector<Run> combinations(const Plan& p, const SweepOptions& o) {
  std::vector<Run> runs;
  std::vector<size_t> idx(p.keys.size(), 0);
  while (true) {
    Run r;
    for (size_t k = 0; k < p.keys.size(); ++k) {
      r.env[p.keys[k]] = p.values[k][idx[k]];
      r.sets.push_back(p.keys[k] + "=" + p.values[k][idx[k]]);
    }
    const std::map<std::string, std::string> varied(r.env);
    for (const auto& [dk, expr] : p.derives) {
      const std::string v = format_number(evaluate(substitute(expr, varied)));
      r.env[dk] = v;
      r.sets.push_back(dk + "=" + v);
    }
    r.sets.insert(r.sets.end(), o.set.begin(), o.set.end());
    char name[32];
    std::snprintf(name, sizeof name, "run_%03zu", runs.size());
    r.dir = (fs::path(o.out) / name).string();
    r.scene = load_scene(o.scene, r.sets);
    runs.push_back(std::move(r));
    size_t k = p.keys.size();
    while (k > 0 && ++idx[k - 1] == p.values[k - 1].size()) idx[--k] = 0;
    if (k == 0) return runs;
  }
}

// Runs r unless its directory holds a complete run of the same scene (summary.json with this scene's
// hash of every resolved value; one stopped by a signal, or of another scene, is run again, its files
// replaced); returns its summary, or null if set-up failed before anything was written.
nlohmann::json run_or_reuse(const Run& r, const SweepOptions& o, SweepResult& res) {
  const std::string summary_path = r.dir + "/summary.json";
  bool done = false, other_scene = false;
  if (fs::exists(summary_path)) {
    std::ifstream in(summary_path);
    try {
      const nlohmann::json j = nlohmann::json::parse(in);
      const nlohmann::json why = j.value("stop_reason", nlohmann::json()), hash = j.value("scene_hash", nlohmann::json());
      other_scene = !hash.is_string() || hash.get<std::string>() != scene_hash(r.scene);
      done = !other_scene && why.is_string() && !j.contains("stop_signal") && why != "interrupted" &&
             why != "terminated" && why.get<std::string>().rfind("signal", 0) != 0;
    } catch (const std::exception&) {}
  }
  if (done) {
    ++res.reused;
    if (o.log) *o.log << "sweep: " << r.dir << ": already run with this scene (summary.json kept)" << std::endl;
  } else {
    std::string settings;
    for (const auto& kv : r.sets) settings += " " + kv;
    if (o.log)
      *o.log << "sweep: " << r.dir << ":" << settings << (other_scene ? " (it held a run of another scene: replaced)" : "")
             << std::endl;
    RunOptions ro;
    ro.out_dir = r.dir;
    ro.stop = o.stop;
    try {
      run_scene(r.scene, ro);
    } catch (const std::exception& e) {
      ++res.failed;
      if (o.log) *o.log << "sweep: " << r.dir << " failed: " << e.what() << std::endl;
    }
  }
  if (!fs::exists(summary_path)) return nullptr;
  std::ifstream in(summary_path);
  nlohmann::json j;
  try { j = nlohmann::json::parse(in); } catch (const std::exception&) { return nlohmann::json::object(); }
  // A run that failed before it wrote (its set-up) leaves another scene's summary: not this run's figures.
  if (!j.is_object() || j.value("scene_hash", nlohmann::json()) != scene_hash(r.scene)) return nullptr;
  return j;
}

// A summary field by its name; a dotted name reaches into nested objects. nullptr if there is none.
const nlohmann::json* field(const nlohmann::json& s, const std::string& name) {
  const nlohmann::json* v = &s;
  for (const auto& part : split(name, '.')) {
    if (!v->is_object() || !v->contains(part)) return nullptr;
    v = &(*v)[part];
  }
  return v;
}

// A --report field the first run's summary does not have is a mistake (it gave an empty column):
// refused, naming the fields there are. The runs done so far are kept and reused by the next call.
void check_report(const nlohmann::json& s, const Run& r, const std::vector<std::string>& report) {
  if (s.value("stop_reason", nlohmann::json()) == "fault") return;  // a fault's summary has no figures
  for (const auto& rep : report) {
    if (field(s, rep)) continue;
    std::string names;
    for (const auto& [k, v] : s.items()) names += (names.empty() ? "" : ", ") + k;
    throw UsageError("--report " + rep + ": " + r.dir + "/summary.json has no such field (it has: " + names + ")");
  }
}

// A table row: the run's values and the reported summary fields.
nlohmann::json table_row(const Run& r, const nlohmann::json& s, const std::vector<std::string>& report) {
  nlohmann::json row = nlohmann::json::object();
  for (const auto& [k, v] : r.env) row[k] = v;
  for (const auto& rep : report) {
    const nlohmann::json* v = field(s, rep);
    row[rep] = v ? *v : nlohmann::json();
  }
  row["steps"] = s.value("steps", nlohmann::json());
  row["wall_seconds"] = s.value("wall_seconds", nlohmann::json());
  row["run"] = r.dir;
  return row;
}

std::string csv_table(const std::vector<std::string>& cols, const std::vector<nlohmann::json>& rows) {
  std::ostringstream csv;
  for (size_t c = 0; c < cols.size(); ++c) csv << (c ? "," : "") << csv_field(cols[c]);
  csv << "\n";
  for (const auto& row : rows) {
    for (size_t c = 0; c < cols.size(); ++c) csv << (c ? "," : "") << csv_field(cell(row.value(cols[c], nlohmann::json()), false));
    csv << "\n";
  }
  return csv.str();
}

// The Markdown table (without the run column) with the observed order of each reported field
// along the first varied key: against the last earlier row with the other varied keys equal.
std::string markdown_table(const std::vector<std::string>& cols, const std::vector<nlohmann::json>& rows,
                           const std::vector<std::string>& keys, const std::vector<std::string>& report) {
  std::ostringstream md;
  md << "|";
  for (size_t c = 0; c + 1 < cols.size(); ++c) md << " " << cols[c] << " |";
  for (const auto& rep : report) md << " order " << rep << " |";
  md << "\n|";
  for (size_t c = 0; c + 1 < cols.size() + report.size(); ++c) md << "---|";
  md << "\n";
  const std::string& res_key = keys[0];
  for (size_t i = 0; i < rows.size(); ++i) {
    const nlohmann::json* prev = nullptr;
    for (size_t j = i; j-- > 0;) {
      bool same = true;
      for (size_t k = 1; k < keys.size(); ++k) same = same && rows[j][keys[k]] == rows[i][keys[k]];
      if (same) { prev = &rows[j]; break; }
    }
    md << "|";
    for (size_t c = 0; c + 1 < cols.size(); ++c) md << " " << cell(rows[i].value(cols[c], nlohmann::json()), true) << " |";
    for (const auto& rep : report) {
      double e0, e1, n0, n1;
      std::string order;
      if (prev && as_number((*prev)[rep], e0) && as_number(rows[i][rep], e1) && as_number((*prev)[res_key], n0) &&
          as_number(rows[i][res_key], n1) && e0 != 0 && e1 != 0 && n0 > 0 && n1 > 0 && n0 != n1) {
        const double p = std::log(std::fabs(e0) / std::fabs(e1)) / std::log(n1 / n0);
        char buf[32];
        std::snprintf(buf, sizeof buf, "%.2f", p);
        order = buf;
      }
      md << " " << order << " |";
    }
    md << "\n";
  }
  return md.str();
}

}  // namespace

SweepResult run_sweep(const SweepOptions& o) {
  const Plan plan = parse_plan(o);
  const std::vector<Run> runs = combinations(plan, o);
  OutputDirectory owned(o.out);  // one sweep at a time in DIR (DirectoryBusy: refused before any run)
  SweepResult res;
  std::vector<nlohmann::json> rows;
  for (const Run& r : runs) {
    if (o.stop && o.stop->load()) break;
    const nlohmann::json s = run_or_reuse(r, o, res);
    if (s.is_null()) continue;
    if (res.runs == 0) check_report(s, r, o.report);
    ++res.runs;
    rows.push_back(table_row(r, s, o.report));
  }
  std::vector<std::string> cols(plan.keys);
  for (const auto& [dk, e] : plan.derives)
    if (std::find(cols.begin(), cols.end(), dk) == cols.end()) cols.push_back(dk);
  for (const std::string& c : o.report)  // each column once (--report steps gave two)
    if (std::find(cols.begin(), cols.end(), c) == cols.end()) cols.push_back(c);
  for (const std::string c : {"steps", "wall_seconds", "run"})
    if (std::find(cols.begin(), cols.end(), c) == cols.end()) cols.push_back(c);
  write_file_atomic((fs::path(o.out) / "sweep.csv").string(), csv_table(cols, rows));
  res.markdown = markdown_table(cols, rows, plan.keys, o.report);
  write_file_atomic((fs::path(o.out) / "sweep.md").string(), res.markdown);
  if (o.table) *o.table << res.markdown << std::flush;
  return res;
}

}  // namespace sphib::app

#include "io/scene.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>
#include <toml++/toml.h>

#include "fluid/factory.hpp"
#include "fluid/common/boundary.hpp"
#include "fluid/common/free_surface.hpp"
#include "io/digest.hpp"
#include "io/scene_checks.hpp"
#include "membrane/shapes.hpp"

namespace sphib {

namespace {

std::string fmt_num(double v) { return number_text(v); }

// Reads typed values by dotted key, records which keys were used and documents each key.
class Reader {
 public:
  Reader(toml::table& root, std::string name, std::set<std::string> overridden)
      : root_(root), name_(std::move(name)), overridden_(std::move(overridden)) {}

  struct Doc {
    std::string key, type, def, range, what;
  };
  std::vector<Doc> docs;
  bool documenting = false;  // collecting the key list: nothing is required

  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    std::ostringstream m;
    m << name_;
    if (overridden_.count(key)) m << ": (--set " << key << ")";
    else if (const toml::node* n = find(key); n && n->source().begin.line) m << ":" << n->source().begin.line;
    m << ": " << key << ": " << what;
    throw SceneError(m.str());
  }

  const toml::node* find(const std::string& key) const { return root_.at_path(key).node(); }
  bool has(const std::string& key) const { return find(key) != nullptr; }

  double number(const std::string& key, double def, const std::string& range, const std::string& what,
                bool required = false, double lo = -INFINITY, bool lo_open = false, double hi = INFINITY) {
    doc(key, "number", required ? "(required)" : fmt_num(def), range, what);
    const toml::node* n = use(key);
    if (!n) {
      if (required && !documenting) fail(key, "missing (required: " + what + ")");
      return record(key, def);
    }
    std::optional<double> v;
    if (n->is_floating_point()) v = n->as_floating_point()->get();
    else if (n->is_integer()) v = static_cast<double>(n->as_integer()->get());
    if (!v) fail(key, "must be a number (got " + type_name(*n) + ")");
    if (!std::isfinite(*v)) fail(key, "must be finite (got " + fmt_num(*v) + ")");
    if ((lo_open ? !(*v > lo) : !(*v >= lo)) || !(*v <= hi))
      fail(key, "value " + fmt_num(*v) + " is out of range (allowed: " + range + ")");
    return record(key, *v);
  }
  double positive(const std::string& key, double def, const std::string& what, bool required = false) {
    return number(key, def, "> 0", what, required, 0.0, true);
  }
  // An integer in [lo, hi], checked on the file's 64-bit value before anything narrows it.
  long integer(const std::string& key, long def, long lo, const std::string& what, bool required = false,
               long hi = std::numeric_limits<long>::max()) {
    const std::string range =
        hi == std::numeric_limits<long>::max() ? ">= " + std::to_string(lo) : "[" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
    doc(key, "integer", required ? "(required)" : std::to_string(def), range, what);
    const toml::node* n = use(key);
    if (!n) {
      if (required && !documenting) fail(key, "missing (required: " + what + ")");
      return record(key, def);
    }
    if (!n->is_integer()) fail(key, "must be an integer (got " + type_name(*n) + ")");
    const std::int64_t v = n->as_integer()->get();
    if (v < lo || v > hi) fail(key, "value " + std::to_string(v) + " is out of range (allowed: " + range + ")");
    return record(key, static_cast<long>(v));
  }
  // The same for a value kept in an int.
  int int32(const std::string& key, int def, int lo, const std::string& what, bool required = false,
            int hi = std::numeric_limits<int>::max()) {
    return static_cast<int>(integer(key, def, lo, what, required, hi));
  }
  bool boolean(const std::string& key, bool def, const std::string& what) {
    doc(key, "boolean", def ? "true" : "false", "true | false", what);
    const toml::node* n = use(key);
    if (!n) return record(key, def);
    if (!n->is_boolean()) fail(key, "must be true or false (got " + type_name(*n) + ")");
    return record(key, n->as_boolean()->get());
  }
  std::string text(const std::string& key, const std::string& def, const std::string& what) {
    doc(key, "string", "\"" + def + "\"", "", what);
    const toml::node* n = use(key);
    if (!n) return record(key, def);
    if (!n->is_string()) fail(key, "must be a string (got " + type_name(*n) + ")");
    if (n->as_string()->get().find('\0') != std::string::npos)
      fail(key, "holds a NUL character (\\u0000), which would cut the text short in the output files");
    return record(key, n->as_string()->get());
  }
  std::string choice(const std::string& key, const std::string& def, const std::vector<std::string>& options,
                     const std::string& what) {
    std::string all;
    for (const auto& o : options) all += (all.empty() ? "" : " | ") + o;
    const std::string v = text(key, def, what);
    docs.back().range = all;
    for (const auto& o : options)
      if (v == o) return v;
    fail(key, "\"" + v + "\" is not allowed (allowed: " + all + ")");
  }
  // A closed set of choices: the words of its table (fluid/common/params.hpp), read as its enum.
  template <class E, std::size_t N>
  E option(const std::string& key, E def, const EnumName<E> (&table)[N], const std::string& what) {
    std::vector<std::string> names;
    for (const auto& e : table) names.emplace_back(e.name);
    const std::string v = choice(key, enum_name(def, table), names, what);
    for (const auto& e : table)
      if (v == e.name) return e.value;
    fail(key, "\"" + v + "\" has no value");  // not reached: choice refused it
  }
  Eigen::Vector2d pair(const std::string& key, const Eigen::Vector2d& def, const std::string& what,
                       bool required = false) {
    doc(key, "[number, number]", required ? "(required)" : "[" + fmt_num(def[0]) + ", " + fmt_num(def[1]) + "]", "",
        what);
    const toml::node* n = use(key);
    if (!n) {
      if (required && !documenting) fail(key, "missing (required: " + what + ")");
      return record(key, def);
    }
    const toml::array* a = n->as_array();
    if (!a || a->size() != 2) fail(key, "must be an array of two numbers");
    Eigen::Vector2d v;
    for (int k = 0; k < 2; ++k) {
      const toml::node& e = *a->get(k);
      if (e.is_floating_point()) v[k] = e.as_floating_point()->get();
      else if (e.is_integer()) v[k] = static_cast<double>(e.as_integer()->get());
      else fail(key, "must be an array of two numbers");
      if (!std::isfinite(v[k])) fail(key, "must be finite");
    }
    return record(key, v);
  }
  // An integer >= lo whose default depends on the machine (described by `def`): 0 when not given,
  // and then not recorded (the run's resolved values stay those of the scene, whatever the machine).
  long machine_default(const std::string& key, long lo, const std::string& def, const std::string& what) {
    doc(key, "integer", def, ">= " + std::to_string(lo), what);
    const toml::node* n = use(key);
    if (!n) return 0;
    if (!n->is_integer()) fail(key, "must be an integer (got " + type_name(*n) + ")");
    const std::int64_t v = n->as_integer()->get();
    if (v < lo) fail(key, "value " + std::to_string(v) + " is out of range (allowed: >= " + std::to_string(lo) + ")");
    return record(key, static_cast<long>(v));
  }
  // A value read by the caller: recorded as the file gives it (TOML text), when given.
  const toml::node* raw(const std::string& key, const std::string& type, const std::string& what) {
    doc(key, type, "", "", what);
    const toml::node* n = use(key);
    if (n && !n->is_table()) {
      std::ostringstream s;
      n->visit([&](const auto& v) { s << v; });
      resolved.emplace_back(key, s.str());
    }
    return n;
  }

  // Every leaf key present but never read is an error.
  void reject_unknown() const { walk(root_, ""); }

  // Every key read, given or not, with the value used in one canonical text (numbers in their
  // shortest exact form): a restart compares them, so a key set to its default matches its absence.
  std::vector<std::pair<std::string, std::string>> resolved;

 private:
  const toml::node* use(const std::string& key) {
    used_.insert(key);
    return find(key);
  }
  template <class T>
  T record(const std::string& key, const T& v) {
    if (!documenting) resolved.emplace_back(key, canonical(v));
    return v;
  }
  static std::string canonical(double v) {
    char buf[32];
    return std::string(buf, std::to_chars(buf, buf + sizeof buf, v).ptr);
  }
  static std::string canonical(long v) { return std::to_string(v); }
  static std::string canonical(bool v) { return v ? "true" : "false"; }
  static std::string canonical(const std::string& v) { return v; }
  static std::string canonical(const Eigen::Vector2d& v) { return "[" + canonical(v[0]) + ", " + canonical(v[1]) + "]"; }
  void doc(const std::string& key, const std::string& type, const std::string& def, const std::string& range,
           const std::string& what) {
    docs.push_back({key, type, def, range, what});
  }
  static std::string type_name(const toml::node& n) {
    switch (n.type()) {
      case toml::node_type::string: return "a string";
      case toml::node_type::integer: return "an integer";
      case toml::node_type::floating_point: return "a number";
      case toml::node_type::boolean: return "a boolean";
      case toml::node_type::array: return "an array";
      case toml::node_type::table: return "a table";
      default: return "a date/time";
    }
  }
  void walk(const toml::table& t, const std::string& prefix) const {
    for (const auto& [k, v] : t) {
      const std::string key = prefix.empty() ? std::string(k.str()) : prefix + "." + std::string(k.str());
      if (used_.count(key)) continue;
      if (const toml::table* sub = v.as_table()) { walk(*sub, key); continue; }
      if (const toml::array* arr = v.as_array(); arr && arr->is_array_of_tables()) {
        for (size_t i = 0; i < arr->size(); ++i) walk(*arr->get(i)->as_table(), key + "[" + std::to_string(i) + "]");
        continue;
      }
      std::ostringstream m;
      m << name_;
      if (overridden_.count(key)) m << ": (--set " << key << ")";
      else if (v.source().begin.line) m << ":" << v.source().begin.line;
      m << ": unknown key '" << key << "' (see `sphib keys` for the keys a scene may have)";
      throw SceneError(m.str());
    }
  }

  toml::table& root_;
  std::string name_;
  std::set<std::string> overridden_;
  std::set<std::string> used_;
};

// ---- Unknown keys, checked before any value is read: a misspelt key is named (with its line and
// the nearest valid key) even when the misspelling leaves a required key missing.

// Edit distance (insertions, deletions, substitutions) between two keys.
size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diag = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}

// "membranes[3].radius" -> "membrane.radius": the keys of one [[membranes]] entry are those of [membrane].
std::string generic_key(const std::string& key) {
  if (key.rfind("membranes[", 0) != 0) return key;
  const size_t close = key.find("].");
  return close == std::string::npos ? key : "membrane." + key.substr(close + 2);
}

// The nearest valid key to `key` (same leaf name in another table first, then the smallest edit
// distance within a third of the leaf's length, at least 2), "" when none is near. Shown as the leaf
// alone when it is in the same table ('mu' for fluid.muu), else in full ('time.dt' for fluid.dt).
std::string nearest_key(const std::string& key, const std::vector<std::string>& known) {
  const std::string g = generic_key(key);
  const size_t dot = g.rfind('.');
  const std::string table = dot == std::string::npos ? "" : g.substr(0, dot + 1);
  const std::string leaf = g.substr(table.size());
  std::string best;
  size_t best_d = std::max<size_t>(2, leaf.size() / 3) + 1;
  for (const std::string& k : known) {
    const size_t kd = k.rfind('.');
    const size_t d = k.substr(kd == std::string::npos ? 0 : kd + 1) == leaf ? 0 : edit_distance(g, k);
    if (d < best_d) best_d = d, best = k;
  }
  if (best.empty()) return "";
  if (!table.empty() && best.rfind(table, 0) == 0 && best.find('.', table.size()) == std::string::npos)
    return best.substr(table.size());
  if (key != g && best.rfind("membrane.", 0) == 0)  // back to this entry's own prefix
    return key.substr(0, key.find("].") + 2) + best.substr(9);
  return best;
}

// Every leaf of the table whose key no scene reads is refused, naming its line (or --set) and the
// nearest valid key. Tables that valid keys live in ([membrane], [domain], ...) are not leaves here:
// a value given in their place is refused by the reader with its type.
void reject_unknown_keys(const toml::table& t, const std::string& prefix, const std::vector<std::string>& known,
                         const std::string& name, const std::set<std::string>& overridden) {
  for (const auto& [k, v] : t) {
    const std::string key = prefix.empty() ? std::string(k.str()) : prefix + "." + std::string(k.str());
    const std::string g = generic_key(key);
    bool leaf = false, table = false;
    for (const std::string& kk : known) {
      leaf |= kk == g;
      table |= kk.size() > g.size() && kk.compare(0, g.size(), g) == 0 && kk[g.size()] == '.';
    }
    const toml::array* arr = v.as_array();
    if (const toml::table* sub = v.as_table(); sub && !leaf && (table || !sub->empty())) {  // an empty [x] of no key: refused
      reject_unknown_keys(*sub, key, known, name, overridden);
      continue;
    }
    if (leaf && arr && arr->is_array_of_tables()) {  // [[membranes]]
      for (size_t i = 0; i < arr->size(); ++i)
        reject_unknown_keys(*arr->get(i)->as_table(), key + "[" + std::to_string(i) + "]", known, name, overridden);
      continue;
    }
    if (leaf || table) continue;  // a value of the wrong kind: the reader names the key and the type
    std::ostringstream m;
    m << name;
    if (overridden.count(key)) m << ": (--set " << key << ")";
    else if (v.source().begin.line) m << ":" << v.source().begin.line;
    m << ": unknown key '" << key << "'";
    if (const std::string near = nearest_key(key, known); !near.empty()) m << ": did you mean '" << near << "'?";
    m << " (see `sphib keys` for the keys a scene may have)";
    throw SceneError(m.str());
  }
}

// Dotted keys of at most kMaxKeyParts parts: the TOML library and the key walks below recurse once per
// part (15 000 parts overflowed the stack).
constexpr int kMaxKeyParts = 64;

// The line of the first dotted key in `text` with more than kMaxKeyParts parts (0 if none), and its
// count. A key may stand at the start of a line, in a table header or inside an inline table, and
// mix bare and quoted parts ("a"."b".c): every run of names joined by dots outside strings counts
// (a run of more than 64 that is not a key is no valid TOML either). Multi-line strings are skipped.
std::pair<int, int> deepest_key(const std::string& text) {
  int line = 1;
  std::string closer;  // inside a multi-line string: its closing quotes
  for (size_t at = 0; at < text.size();) {
    const size_t end = std::min(text.find('\n', at), text.size());
    const std::string l = text.substr(at, end - at);
    size_t i = 0;
    if (!closer.empty()) {
      const size_t c = l.find(closer);
      if (c == std::string::npos) i = l.size();
      else i = c + 3, closer.clear();
    }
    int dots = 0, most = 0;
    for (; i < l.size(); ++i) {
      const char c = l[i];
      if (c == '"' || c == '\'') {  // a string: a quoted part of a key, or a value
        if (l.compare(i, 3, std::string(3, c)) == 0) {
          const size_t close = l.find(std::string(3, c), i + 3);
          if (close == std::string::npos) { closer = std::string(3, c); break; }
          i = close + 2;
          continue;
        }
        for (++i; i < l.size() && l[i] != c; ++i)
          if (c == '"' && l[i] == '\\') ++i;
        continue;
      }
      if (c == '.') { most = std::max(most, ++dots); continue; }
      if (std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '+' || c == ' ' || c == '\t') continue;
      if (c == '#') break;
      dots = 0;  // '=', '{', ',', '[', ...: a run of names ends
    }
    if (most + 1 > kMaxKeyParts) return {line, most + 1};
    at = end + 1;
    ++line;
  }
  return {0, 0};
}

// Applies key=value to the table, creating intermediate tables. `membrane.X` also reaches the
// only element of a [[membranes]] array.
std::string apply_override(toml::table& root, const std::string& kv, const std::string& name) {
  const auto eq = kv.find('=');
  if (eq == std::string::npos || eq == 0)
    throw SceneError(name + ": --set " + kv + ": expected key=value (for example grid.nx=32)");
  std::string key = kv.substr(0, eq);
  const std::string val = kv.substr(eq + 1);
  if (const long parts = std::count(key.begin(), key.end(), '.') + 1; parts > kMaxKeyParts)
    throw SceneError(name + ": --set " + key.substr(0, 40) + "...: a key of " + std::to_string(parts) +
                     " dotted parts (a scene's keys have a few; at most " + std::to_string(kMaxKeyParts) + ")");
  if (val.find_first_of("\n\r") != std::string::npos)  // would add keys of its own: one value, one line
    throw SceneError(name + ": (--set " + key + "): the value holds a line break (one value per --set)");
  toml::table parsed;
  try {
    parsed = toml::parse("v = " + val);
  } catch (const toml::parse_error&) {
    parsed.insert_or_assign("v", val);  // a bare word: a string
  }
  if (parsed.size() != 1) throw SceneError(name + ": (--set " + key + "): the value is not one TOML value");
  if (key.rfind("membrane.", 0) == 0 && !root.contains("membrane")) {
    if (toml::array* arr = root["membranes"].as_array(); arr && arr->size() == 1)
      key = "membranes[0]." + key.substr(9);
  }
  // Walk/create the tables of the dotted key.
  toml::table* t = &root;
  size_t start = 0;
  while (true) {
    const size_t dot = key.find('.', start);
    std::string part = key.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
    if (part.empty()) throw SceneError(name + ": --set " + kv + ": empty key component");
    if (dot == std::string::npos) {
      t->insert_or_assign(part, *parsed.get("v"));
      break;
    }
    const auto br = part.find('[');
    if (br != std::string::npos) {  // membranes[0]
      const std::string arr_name = part.substr(0, br);
      char* end = nullptr;
      const long idx = std::strtol(part.c_str() + br + 1, &end, 10);
      toml::array* arr = (*t)[arr_name].as_array();
      if (!arr || end != part.c_str() + part.size() - 1 || *end != ']' || idx < 0 ||
          idx >= static_cast<long>(arr->size()) || !arr->get(idx)->is_table())
        throw SceneError(name + ": --set " + kv + ": no table " + part);
      t = arr->get(idx)->as_table();
    } else {
      if (!t->contains(part)) t->insert(part, toml::table{});
      t = (*t)[part].as_table();
      if (!t) throw SceneError(name + ": --set " + kv + ": " + part + " is not a table");
    }
    start = dot + 1;
  }
  return key;
}

SolverKind solver_kind(const std::string& s) {
  if (s == "cholmod_supernodal") return SolverKind::CholmodSupernodal;
  if (s == "cholmod_simplicial") return SolverKind::CholmodSimplicial;
  if (s == "umfpack") return SolverKind::Umfpack;
  if (s == "pcg") return SolverKind::Pcg;
  if (s == "fft") return SolverKind::Fft;
  if (s == "pcg_fft") return SolverKind::PcgFft;
  if (s == "pcg_cholmod") return SolverKind::PcgCholmod;
  return SolverKind::Auto;
}

// The membrane's material and reference state (membrane/law.hpp): law and moduli, bending, the
// stress-free shape, the stiff-force filter.
void read_material(Reader& r, const std::string& p, MembraneScene& m) {
  std::vector<std::string> laws;
  std::string law_help = "tension law: ";
  for (const LawInfo& l : tension_laws()) {
    laws.push_back(l.name);
    law_help += l.name + " (" + l.help + "); ";
  }
  m.law = r.choice(p + "law", "hookean", laws, law_help.substr(0, law_help.size() - 2));
  const bool hookean = m.law == "hookean";
  // The modulus: the paper's T0 for the Hookean law (Eq. 47), or Es (any law): one of them.
  const bool has_T0 = r.has(p + "T0"), has_Es = r.has(p + "Es");
  if (has_T0 && !hookean) r.fail(p + "T0", "is the Hookean law's modulus (Eq. 47); law \"" + m.law + "\" takes Es");
  if (has_T0 && has_Es) r.fail(p + "Es", "give T0 or Es, not both (T0 is the Hookean law's Es)");
  if (r.documenting || has_T0 || (hookean && !has_Es))
    m.Es = r.number(p + "T0", 1.0, ">= 0", "Young's modulus T0 of Eq. (47): law = \"hookean\"'s Es (give T0 or Es)",
                    !r.documenting, 0.0);
  if (r.documenting || has_Es || !hookean)
    m.Es = r.number(p + "Es", 1.0, ">= 0",
                    "the law's modulus (hookean: T0; neo_hookean, skalak: the shear modulus; inextensible: the penalty "
                    "modulus, large against the flow's stresses)",
                    !r.documenting, 0.0);
  for (const LawInfo& l : tension_laws())
    for (const LawParam& q : l.params) {
      const bool own = l.name == m.law;
      if (!own && !r.documenting) {
        if (r.has(p + q.name)) r.fail(p + q.name, "applies to law = \"" + l.name + "\" only (this membrane's law is \"" + m.law + "\")");
        continue;
      }
      const double v = r.number(p + q.name, q.value, "[" + fmt_num(q.min) + ", " + fmt_num(q.max) + "]", q.help, false,
                                q.min, false, q.max);
      if (own) m.law_params.push_back(v);
    }
  m.Eb = r.number(p + "Eb", 0.0, ">= 0", "bending modulus Eb: energy Eb/2 int (kappa - kappa0)^2 dl (0: no bending)", false, 0.0);
  if (r.documenting || r.has(p + "tension_cutoff"))
    m.tension_cutoff = r.number(p + "tension_cutoff", 0.0, ">= 0",
                                "the tension's modes along the membrane shorter than this length are removed before the "
                                "force, so stretching modes the lattice cannot carry exert none (default: 2 max(dx, dy) "
                                "for law = \"inextensible\", whose stiff penalty they destabilise; 0 for the others; "
                                "docs/membrane_validation.md)",
                                false, 0.0);
  m.reference = r.choice(p + "reference", "circle", {"circle", "initial"},
                         "the stress-free shape: circle (of radius r0, markers uniform in its arclength: the paper's) or "
                         "initial (the initial shape shrunk by 1/prestretch)");
  const bool circle_ref = m.reference == "circle";
  if (r.documenting || circle_ref) m.r0 = r.positive(p + "r0", 0.5, "rest radius r0 of reference = \"circle\": rest length L0 = 2 pi r0", !r.documenting);
  else if (r.has(p + "r0")) r.fail(p + "r0", "is the radius of reference = \"circle\"; with reference = \"initial\" the initial shape is the reference");
  if (r.documenting || !circle_ref)
    m.prestretch = r.positive(p + "prestretch", 1.0, "reference = \"initial\": the initial shape is the reference stretched by this factor (1: stress-free)");
  else if (r.has(p + "prestretch")) r.fail(p + "prestretch", "applies to reference = \"initial\" only");
  if (r.documenting || r.has(p + "kappa0")) {
    m.spontaneous = !r.documenting;
    m.kappa0 = r.number(p + "kappa0", 0.0, "finite", "uniform spontaneous curvature of the bending energy (default: the reference shape's curvature)");
    if (!r.documenting && m.Eb == 0.0) r.fail(p + "kappa0", "is the bending energy's spontaneous curvature: set Eb > 0 too");
  }
  m.semi_implicit = r.boolean(p + "semi_implicit", m.Eb > 0.0 || !hookean,
                              "take the membrane's stiff modes semi-implicitly (coupling/stiff_force.hpp), so stiff "
                              "membranes run at the step the flow needs (default: with bending or a law other than hookean)");
  m.stiff_residual = r.boolean(p + "stiff_residual", false,
                               "the semi-implicit force predicts the membrane's next velocity with the measured residual "
                               "of its model (steady shapes as accurate as the explicit force's at large steps; its "
                               "largest stable step 0.65 to 1.3 times the default's; docs/membranes.md)");
  if (!r.documenting && m.stiff_residual && !m.semi_implicit)
    r.fail(p + "stiff_residual", "refines the semi-implicit force: set semi_implicit = true too");
}

void read_membrane(Reader& r, const std::string& p, MembraneScene& m) {
  m.shape = r.choice(p + "shape", "circle", {"circle", "ellipse", "points"},
                     "initial shape: circle (radius), ellipse (rx, ry) or points (a closed point list)");
  read_material(r, p, m);
  m.nb = r.int32(p + "nb", 128, 4, "number of markers Nb", false, kMaxMarkers);
  const Eigen::Vector2d c = r.pair(p + "centre", Eigen::Vector2d::Zero(), "centre of the initial circle/ellipse");
  m.cx = c[0];
  m.cy = c[1];
  m.radius = r.positive(p + "radius", m.r0, "circle radius (default r0: at rest)", !r.documenting && m.reference != "circle" && m.shape == "circle");
  m.rx = r.positive(p + "rx", 0.75, "ellipse half-axis along x");
  m.ry = r.positive(p + "ry", 0.5, "ellipse half-axis along y");
  if (r.documenting || m.shape == "ellipse")
    m.spacing = r.choice(p + "spacing", "angle", {"angle", "arclength"},
                         "the ellipse's markers: uniform in the angle theta, X = (rx cos, ry sin)(theta) (the paper's; "
                         "stretched against a uniform rest spacing), or uniform in its arclength (an inextensible "
                         "membrane whose rest length is the perimeter starts unstretched)");
  else if (r.has(p + "spacing"))
    r.fail(p + "spacing", "applies to shape = \"ellipse\" only (circles and point lists are spaced by arclength)");
  m.h_star = r.number(p + "h_star", 0.0, ">= 0", "spreading smoothing length h* (0: h_star_over_h * h)", false, 0.0);
  m.h_star_over_h = r.positive(p + "h_star_over_h", 1.4, "h* / h when h_star is 0");
  m.fixed = r.boolean(p + "fixed", false, "hold the markers in place (fixed membrane)");
  m.viscosity_ratio = r.number(p + "viscosity_ratio", 1.0, "[0.01, 100]",
                               "viscosity contrast lambda = mu_in / mu_out: the fluid the membrane encloses has viscosity "
                               "lambda fluid.mu (method eulerian; docs/viscosity_contrast.md)",
                               false, 0.01, false, 100.0);
  const toml::node* pts = r.raw(p + "points", "array of [x, y]", "closed point list for shape = \"points\"");
  if (m.shape == "points") {
    const toml::array* a = pts ? pts->as_array() : nullptr;
    if (!a) r.fail(p + "points", "shape = \"points\" needs points = [[x, y], ...]");
    m.points.resize(static_cast<int>(a->size()), 2);
    for (size_t k = 0; k < a->size(); ++k) {
      const toml::array* e = a->get(k)->as_array();
      if (!e || e->size() != 2) r.fail(p + "points", "each point must be [x, y]");
      for (int d = 0; d < 2; ++d) {
        auto v = e->get(d)->value<double>();
        if (!v || !std::isfinite(*v)) r.fail(p + "points", "each point must be two finite numbers");
        m.points(static_cast<int>(k), d) = *v;
      }
    }
  }
}

const std::vector<std::string>& known_keys();

// The domain, its walls and their velocities.
void read_domain(Reader& r, Scene& s) {
  FluidParams& f = s.sim.fluid;
  const Eigen::Vector2d xr = r.pair("domain.x", {0.0, 1.0}, "x extent [x0, x1]");
  const Eigen::Vector2d yr = r.pair("domain.y", {0.0, 1.0}, "y extent [y0, y1]");
  if (!(xr[1] > xr[0])) r.fail("domain.x", "must satisfy x0 < x1");
  if (!(yr[1] > yr[0])) r.fail("domain.y", "must satisfy y0 < y1");
  f.domain.x0 = xr[0]; f.domain.x1 = xr[1]; f.domain.y0 = yr[0]; f.domain.y1 = yr[1];
  f.domain.periodic_x = r.boolean("domain.periodic_x", true, "periodic in x (else no-slip walls at x0 and x1)");
  f.domain.periodic_y = r.boolean("domain.periodic_y", false, "periodic in y (else no-slip walls at y0 and y1)");
  const char* sides[4] = {"left", "right", "bottom", "top"};
  // Sides of a kind other than a no-slip wall (fluid/common/boundary_rule.hpp), each an array of side
  // names: open (free space), inflow, outflow.
  auto read_sides = [&](const char* key, SideKind kind, const char* help) {
    const toml::node* op = r.raw(key, "array of strings", help);
    if (!op) return;
    const toml::array* a = op->as_array();
    if (!a) r.fail(key, "must be an array of side names (left, right, bottom, top)");
    for (const auto& e : *a) {
      const auto v = e.value<std::string>();
      const int k = v ? static_cast<int>(std::find(sides, sides + 4, *v) - sides) : 4;
      if (k == 4) r.fail(key, "allowed side names: left, right, bottom, top");
      if (f.domain.is_periodic(static_cast<Side>(k)))
        r.fail(key, std::string("the ") + sides[k] + " side is periodic (domain.periodic_" + (k < 2 ? "x" : "y") + ")");
      if (f.domain.bounded[k] != SideKind::NoSlip)
        r.fail(key, std::string("the ") + sides[k] + " side is already " + side_kind_name(f.domain.bounded[k]));
      f.domain.bounded[k] = kind;
    }
  };
  read_sides("domain.open", SideKind::Open,
             "sides open to free space, from left, right, bottom, top: no wall there (free-surface "
             "methods; a particle crossing one stops the run)");
  read_sides("domain.inflow", SideKind::Inflow,
             "sides where a prescribed velocity enters (method eulerian): the side's walls.<side> velocity shaped by "
             "domain.inflow_profile");
  read_sides("domain.outflow", SideKind::Outflow,
             "sides where the flow leaves (method eulerian): zero normal gradient of the velocity, phi = 0 there");
  read_sides("domain.free_slip", SideKind::FreeSlip,
             "free-slip walls (method eulerian): impermeable and shear-free, normal velocity 0 and zero normal "
             "gradient of the tangential velocity there");
  const std::string profile = r.choice("domain.inflow_profile", "none", {"none", "uniform", "parabolic"},
                                       "the inflow's velocity along its side: uniform (walls.<side> everywhere) or "
                                       "parabolic (4 s (1 - s) walls.<side>, s in [0, 1] along the side)");
  f.domain.inflow_profile = profile == "uniform" ? InflowProfile::Uniform
                            : profile == "parabolic" ? InflowProfile::Parabolic
                                                     : InflowProfile::None;
  bool inflow = false;
  for (int k = 0; k < 4; ++k) {
    const std::string key = std::string("walls.") + sides[k];
    const bool given = r.has(key);
    const Side side = static_cast<Side>(k);
    f.domain.wall_velocity[k] = r.pair(key, Eigen::Vector2d::Zero(), std::string("velocity of the ") + sides[k] +
                                                                         " wall (of an inflow side: the inflow's velocity)");
    const SideKind kind = f.domain.kind(side);
    if (kind == SideKind::Inflow) {
      inflow = true;
      const double normal = (k < 2 ? f.domain.wall_velocity[k].x() : f.domain.wall_velocity[k].y()) * (k % 2 == 0 ? 1.0 : -1.0);
      if (!r.documenting && !(normal > 0))
        r.fail(key, std::string("the inflow through the ") + sides[k] + " side needs a velocity pointing into the domain");
      if (!r.documenting && f.domain.inflow_profile == InflowProfile::None)
        r.fail("domain.inflow_profile", "an inflow needs its profile: \"uniform\" or \"parabolic\"");
    } else if (given && !f.domain.is_wall(side)) {
      r.fail(key, std::string("a wall velocity is given on ") +
                      (kind == SideKind::Periodic ? "a periodic side"
                       : kind == SideKind::FreeSlip ? "a free_slip side (domain.free_slip: a wall at rest)"
                                                    : std::string("an ") + side_kind_name(kind) + " side"));
    }
    if (const std::string why = wall_moves_normally(f.domain, k); !why.empty()) r.fail(key, why);
  }
  if (!inflow && profile != "none") r.fail("domain.inflow_profile", "is given without an inflow side (domain.inflow)");
}

// Resolution, kernel, the fluid and its method's parameters.
void read_fluid(Reader& r, Scene& s) {
  FluidParams& f = s.sim.fluid;
  f.nx = r.int32("grid.nx", 0, 2, "particles along x (Eq. 68)", true);
  f.ny = r.int32("grid.ny", 0, 2, "particles along y (Eq. 68)", true);
  f.h_over_dx = r.number("kernel.h_over_dx", 1.2, "> max(dx, dy)/(dx + dy) (0.5 when dx = dy)",
                         "smoothing length h = h_over_dx (dx + dy)/2; support 2h", false, 0.0, true);
  if (!r.documenting) {
    if (const std::string why = lattice_too_large(f); !why.empty()) r.fail("grid.nx", why);
    if (const std::string why = kernel_too_narrow(f); !why.empty()) r.fail("kernel.h_over_dx", why);
  }
  // Fluid
  f.rho = r.positive("fluid.rho", 1.0, "density rho", true);
  f.mu = r.positive("fluid.mu", 1.0, "dynamic viscosity mu", true);
  s.sim.body_force = r.pair("fluid.body_force", Eigen::Vector2d::Zero(), "body force per unit volume [Fx, Fy]");
  f.gravity = r.pair("fluid.gravity", Eigen::Vector2d::Zero(),
                     "gravity, an acceleration [gx, gy] (free-surface methods: wcsph, isph): wcsph takes the hydrostatic "
                     "initial density (Afanasiev et al. Eq. 28) and B (Eq. 27) from it, isph adds it to u* (Eq. 22); it may not "
                     "point along a periodic axis or at an open side");
  f.convection = r.boolean("fluid.convection", true, "Navier-Stokes (true) or Stokes (false: no convection operator)");
  f.method = s.method;
  const std::string projection = r.choice(
      "fluid.projection", "auto", {"auto", "exact", "approximate"},
      "Poisson operator of the projection: exact (D G: the projected velocity is discretely divergence-free), "
      "approximate (the paper's Morris Laplacian, Eq. 31); auto: exact for eulerian, approximate for lagrangian and isph");
  if (projection != "auto" && s.method == FluidMethod::Wcsph) r.fail("fluid.projection", "does not apply to method \"wcsph\" (no projection)");
  if (f.domain.any_through()) {  // inflow and outflow: the fixed lattice's images (EPSPH)
    const char* key = "domain.inflow";
    for (int k = 0; k < 4; ++k)
      if (f.domain.kind(static_cast<Side>(k)) == SideKind::Outflow) key = "domain.outflow";
    for (int k = 0; k < 4; ++k)
      if (f.domain.kind(static_cast<Side>(k)) == SideKind::Inflow) key = "domain.inflow";
    if (s.method != FluidMethod::Eulerian)
      r.fail(key, std::string("inflow and outflow sides are available for method \"eulerian\" only (not \"") +
                      to_string(s.method) + "\")");
    const std::string refusal = stream_function_refusal(f.domain);
    if (projection == "exact" && !refusal.empty())
      r.fail("fluid.projection", "\"exact\" needs a stream function of the domain's sides (" + refusal +
                                     "); use \"approximate\"");
  }
  for (int k = 0; k < 4; ++k)  // free-slip walls: per-component images on the fixed lattice (EPSPH)
    if (f.domain.kind(static_cast<Side>(k)) == SideKind::FreeSlip && s.method != FluidMethod::Eulerian)
      r.fail("domain.free_slip", std::string("a free-slip side (\"") + side_name(static_cast<Side>(k)) +
                                     "\") is available for method \"eulerian\" only (not \"" + to_string(s.method) + "\")");
  if (projection == "exact" && s.method == FluidMethod::Lagrangian)
    r.fail("fluid.projection", "\"exact\" is available for method \"eulerian\" only (lagrangian: \"approximate\")");
  f.projection = projection == "approximate" ? Projection::Approximate
                 : projection == "exact"     ? Projection::Exact
                                             : Projection::Auto;
  f.lagrangian.reinit_every = r.int32(
      "lagrangian.reinit_every", 0, 0, "LPSPH: put the particles back on the lattice every so many steps (0: never)");
  f.lagrangian.min_kernel_sum = r.number("lagrangian.min_kernel_sum", 0.5, "[0, 1]",
                                         "LPSPH: stop when a particle's kernel sum sum_j V_j W_ij falls below this",
                                         false, 0.0, false, 1.0);
  f.wcsph.eos = r.option("wcsph.eos", Eos::Morris, kEos, "WCSPH equation of state");
  f.wcsph.c = r.number("wcsph.c", 0.0, ">= 0", "WCSPH speed of sound (0: 10 u_scale, about 1% density variation)",
                       false, 0.0);
  f.wcsph.gamma = r.positive("wcsph.gamma", 7.0, "Tait exponent");
  f.wcsph.xsph = r.number("wcsph.xsph", 0.0, "[0, 1]", "XSPH epsilon (0: off)", false, 0.0, false, 1.0);
  f.wcsph.walls = r.option("wcsph.walls", WcsphWalls::Virtual, kWcsphWalls,
                           "WCSPH walls: Morris virtual particles or the Lennard-Jones repulsion of Coelho et al.");
  f.wcsph.u_scale = r.positive("wcsph.u_scale", 1.0, "expected maximum speed (sets c when wcsph.c = 0)");
  f.wcsph.integrator = r.option("wcsph.integrator", Integrator::Leapfrog, kIntegrators,
                                "WCSPH time stepping: leapfrog (Vukcevic Eq. 22, summation density) or predictor_corrector "
                                "(Afanasiev et al. Eqs. 19-21, continuity density; needed for a free surface)");
  f.wcsph.alpha = r.number("wcsph.alpha", 0.0, ">= 0", "artificial viscosity alpha of Monaghan (1992) (0: off)", false, 0.0);
  f.wcsph.smooth_every = static_cast<int>(r.integer(
      "wcsph.smooth_every", 0, 0, "density smoothing (Afanasiev et al. Eq. 29) every so many steps (predictor_corrector; 0: off)"));
  f.isph.viscous = r.option("isph.viscous", IsphViscous::Explicit, kIsphViscous,
                            "ISPH's viscous predictor: explicit (Afanasiev et al. Eq. 22) or crank_nicolson (the "
                            "projection core's Eq. 28)");
  f.isph.poisson_rtol = r.number("isph.poisson_rtol", 1e-8, "(0, 1e-4]",
                                 "ISPH's Poisson CG stops at |r| <= rtol |b| (or a backward error of 1e-14)", false, 0.0,
                                 true, 1e-4);
  f.isph.poisson_refresh = static_cast<int>(r.integer(
      "isph.poisson_refresh", 8, 1, "ISPH's Poisson CG: a new preconditioner factorisation after a solve that needed more "
                                    "than this many iterations"));
  f.wcsph.wall_pressure = r.option("wcsph.wall_pressure", WallPressure::Rest, kWallPressures,
                                   "pressure of the wall particles (predictor_corrector): rest (p(rho0)), eq30 (Afanasiev et al. "
                                   "Eq. 30), extrapolated (Eq. 30 normalised, with the hydrostatic term of Adami et al. 2012)");
}

// The fluid's initial region and its free surface (fluid/common/free_surface.hpp).
void read_free_surface(Reader& r, Scene& s) {
  FluidParams& f = s.sim.fluid;
  FluidRegion& fill = f.free_surface.fill;
  const std::string shape = r.choice("fill.shape", "domain", {"domain", "block", "circle"},
                                     "where the fluid is at t = 0: the whole domain, a block (fill.x, fill.y) or a circle "
                                     "(fill.centre, fill.radius); a block or circle leaves a free surface (free-surface methods)");
  fill.shape = shape == "block" ? FluidRegion::Shape::Block : shape == "circle" ? FluidRegion::Shape::Circle : FluidRegion::Shape::Domain;
  const Eigen::Vector2d fx = r.pair("fill.x", {f.domain.x0, f.domain.x1}, "the block's x extent [x0, x1] (default: the domain's)");
  const Eigen::Vector2d fy = r.pair("fill.y", {f.domain.y0, f.domain.y1}, "the block's y extent [y0, y1] (default: the domain's)");
  fill.x0 = fx[0], fill.x1 = fx[1], fill.y0 = fy[0], fill.y1 = fy[1];
  fill.centre = r.pair("fill.centre", Eigen::Vector2d::Zero(), "the circle's centre");
  fill.radius = r.positive("fill.radius", 0.5, "the circle's radius", !r.documenting && shape == "circle");
  fill.arrangement = r.choice("fill.arrangement", "lattice", {"lattice", "rings"},
                              "particles: the lattice sites inside the region, or (circles) a centre particle and rings "
                              "k = 1..n of 6k particles at radius k dx (dx = dy), 1 + 3n(n+1) particles") == "rings"
                         ? FluidRegion::Arrangement::Rings
                         : FluidRegion::Arrangement::Lattice;
  if (const toml::node* g = r.raw("fill.velocity_gradient", "[[number, number], [number, number]]",
                                  "initial velocity u0 = G x (rows of G), e.g. the droplet's [[1, 0], [0, -1]]")) {
    const toml::array* a = g->as_array();
    Eigen::Matrix2d G;
    if (!a || a->size() != 2) r.fail("fill.velocity_gradient", "must be two rows [[a, b], [c, d]]");
    for (int i = 0; i < 2; ++i) {
      const toml::array* row = a->get(i)->as_array();
      if (!row || row->size() != 2) r.fail("fill.velocity_gradient", "must be two rows [[a, b], [c, d]]");
      for (int j = 0; j < 2; ++j) {
        const auto v = row->get(j)->value<double>();
        if (!v || !std::isfinite(*v)) r.fail("fill.velocity_gradient", "must hold four finite numbers");
        G(i, j) = *v;
      }
    }
    s.sim.initial_velocity = [G](double x, double y) -> Eigen::Vector2d { return G * Eigen::Vector2d(x, y); };
  }
  FreeSurfaceParams& fs = f.free_surface;
  fs.detection = r.option("free_surface.detection", SurfaceDetection::Auto, kSurfaceDetections,
                          "free-surface particles (p = 0): dilts (Dilts 2000), divergence (Afanasiev et al. Eq. 26: div r < "
                          "2 beta); auto: the paper's choice for the method (wcsph: dilts, isph: divergence), none without a "
                          "free surface");
  fs.beta = r.number("free_surface.beta", 0.75, "(0, 1)", "Eq. (26)'s beta (the paper's best: 0.75 with h/dx = 1.1)", false,
                     0.0, true, 1.0);
  if (fs.beta == 1.0) r.fail("free_surface.beta", "value 1 is out of range (allowed: (0, 1))");
  fs.dilts_radius = r.number("free_surface.dilts_radius", 1.0, "(0, 1]",
                             "Dilts' circle radius over h (a neighbour closer than twice it covers an arc of the circle)",
                             false, 0.0, true, 1.0);
}

// The free-surface methods' regularisation (issue 29): ISPH's particle shifting (fluid/moving/shifting.hpp),
// WCSPH's delta-SPH density diffusion (fluid/moving/wcsph.hpp).
void read_regularisation(Reader& r, Scene& s) {
  FluidParams& f = s.sim.fluid;
  f.isph.scheme = r.option("isph.scheme", IsphScheme::Consistent, kIsphSchemes,
                           "ISPH's operators: consistent (a fluid at rest stays at rest: the pressure gradient exact for a "
                           "linear pressure on the initial arrangement, the Poisson rows beside the free surface mirrored, "
                           "no Lennard-Jones push; fluid/moving/isph.hpp) or paper (Afanasiev et al.'s Eqs. 13, 17 as before)");
  f.isph.shifting = r.option("isph.shifting", Shifting::Auto, kShiftings,
                             "ISPH's particle shifting after each step: fickian (Lind et al. 2012, with their free-surface "
                             "correction), xu (Xu et al. 2009), none (Afanasiev et al.'s Eq. 25 alone); auto: fickian with "
                             "isph.scheme = consistent, none with paper");
  f.isph.shifting_A = r.number("isph.shifting_A", 2.0, "> 0", "Fickian shifting's D = A h |u| dt (Lind et al. 2012: A in [1, 6])",
                               false, 0.0, true);
  f.wcsph.delta = r.number("wcsph.delta", 0.0, ">= 0",
                           "delta-SPH density diffusion delta h c sum_j V_j psi_ij . grad W (Antuono et al. 2010, 2012; "
                           "predictor_corrector; 0: off, 0.1: theirs)",
                           false, 0.0);
}

// A dam break's gate (fluid/common/walls.hpp, append_gate): present when the scene has [gate].
void read_gate(Reader& r, Scene& s) {
  GateParams& g = s.sim.fluid.gate;
  g.on = r.has("gate");
  if (!g.on && !r.documenting) return;  // no gate keys in the resolved scene (a checkpoint's restart)
  g.x = r.number("gate.x", 0.0, "inside the domain", "the gate's face: a plate of wall particles on the line x = gate.x, "
                 "the fluid on its low side (ISPH, WCSPH)", g.on);
  g.speed = r.number("gate.speed", 0.0, "> 0", "the gate's lift speed, m/s (constant from gate.start on)", g.on, 0.0, true);
  g.start = r.number("gate.start", 0.0, ">= 0", "when the gate starts to lift, s", false, 0.0);
  if (g.on && s.method != FluidMethod::Isph && s.method != FluidMethod::Wcsph)
    r.fail("gate", "a gate is available for methods \"isph\" and \"wcsph\" only (the moving particles' walls)");
}

// The time step, the run's length and the linear solvers.
void read_time_and_solvers(Reader& r, Scene& s) {
  FluidParams& f = s.sim.fluid;
  f.dt = r.positive("time.dt", 0.0, "time step", true);
  s.t_end = r.positive("time.end", 0.0, "end time (upper bound when steady_eps is set)", true);
  s.max_steps = r.integer("time.max_steps", 0, 0, "stop after this many steps (0: no limit)");
  s.steady_eps = r.number("time.steady_eps", 0.0, ">= 0", "stop at steady state, Eqs. (81)-(82), when max(rms dp, rms du) < steady_eps dt (0: off)", false, 0.0);
  // Solvers
  const std::vector<std::string> kinds{"auto", "cholmod_supernodal", "cholmod_simplicial", "umfpack"};
  std::vector<std::string> cn_kinds(kinds);
  cn_kinds.push_back("pcg");
  cn_kinds.push_back("fft");
  for (const char* k : {"pcg_fft", "pcg_cholmod"}) cn_kinds.push_back(k);
  f.cn_solver = solver_kind(r.choice("solver.crank_nicolson", "auto", cn_kinds,
                                     "Crank-Nicolson solver (auto: fast transforms when the matrix has the lattice structure (eulerian, every domain: FFT along periodic axes, DCT-II or DST-II in x between walls, banded Cholesky in y between walls), else warm-started Jacobi-PCG when the Gershgorin bound nu dt max|lap_ii| <= 0.5, else CHOLMOD, simplicial or supernodal by the size of the factor; auto, moving particles (lagrangian): pcg_fft where the lattice has an FFT solver, else Jacobi-PCG when the bound is <= 40, else pcg_cholmod; pcg_fft, pcg_cholmod (moving particles only): CG warm-started and preconditioned by the FFT solver of the initial lattice, or by a CHOLMOD factor of an earlier step's matrix refactorised when a solve needs more than 8 iterations)"));
  std::vector<std::string> poisson_kinds(kinds);
  poisson_kinds.push_back("fft");
  for (const char* k : {"pcg_fft", "pcg_cholmod"}) poisson_kinds.push_back(k);
  f.poisson_solver = solver_kind(r.choice("solver.poisson", "auto", poisson_kinds,
                                          "Poisson solver (auto: fast transforms when the matrix has the lattice structure (eulerian, every domain: FFT along periodic axes, DCT-II or DST-II in x between walls, banded Cholesky in y between walls), else CHOLMOD, simplicial or supernodal by the size of the factor; auto, moving particles (lagrangian): pcg_fft where the lattice has an FFT solver, else pcg_cholmod; auto, isph: pcg_cholmod with a free surface, CHOLMOD supernodal for a full tank; pcg_fft, pcg_cholmod as for solver.crank_nicolson, moving particles only)"));
  f.viscosity_rtol = r.number("solver.viscosity_rtol", 1e-8, "(0, 1e-4]",
                              "a viscosity contrast's Crank-Nicolson conjugate gradients stop at |r| <= rtol |b| (or a "
                              "backward error of 1e-14)", false, 0.0, true, 1e-4);
  s.sim.markers.eps = r.positive("solver.marker_eps", 1e-12, "fixed-point tolerance on max |g| (Eq. 59)");
  s.sim.markers.max_iter = r.int32("solver.marker_max_iter", 50, 1, "fixed-point iteration limit");
  s.sim.markers.linear_step = r.number(
      "solver.marker_linear_step", 1e-6, "(0, 1]",
      "the largest |g| the marker update accepts by linearisation (one interpolation less), as a fraction of a lattice "
      "spacing: the neglected term dt/4 |grad grad U| |g|^2 must stay below solver.marker_eps/2",
      false, 0.0, true, 1.0);
  s.sim.markers.newton = r.boolean(
      "solver.marker_newton", false,
      "linearised step of the marker update: a Newton step (I - dt/2 dU/dX)^{-1} g (zero linear residual: only "
      "the quadratic term dt/4 |grad grad U| |step|^2 must stay below solver.marker_eps, one interpolation per step "
      "at a solver.marker_linear_step of 1e-4) instead of the fixed-point step g; needs an interpolation with a "
      "gradient (divergence_free, bspline, spreading_kernel)");
  s.sim.markers.keep_area = r.boolean(
      "solver.marker_keep_area", false,
      "the marker update's area constraint: each free membrane's U^{n+1} loses the least normal velocity that "
      "would change the area its spline curve encloses over the trapezoidal step (the markers' own error in "
      "carrying a divergence-free flux), so that each step keeps that area to the update's residual; false: the "
      "velocities as interpolated");
  s.sim.markers.extrapolate =
      r.choice("solver.marker_predictor", "extrapolated", {"extrapolated", "euler"},
               "first iterate of the marker update: extrapolated (X^n + dt (3/2 U^n - 1/2 U^{n-1}), no interpolation, "
               "O(dt^3) from the root) or euler (the paper's Eq. 58, X^n + dt U^{n+1}(X^n)); the same root within "
               "solver.marker_eps") == "extrapolated";
  const std::string interp = r.choice(
      "coupling.interpolation", "auto", {"auto", "divergence_free", "bspline", "sph", "spreading_kernel"},
      "marker velocity: divergence_free (curl of the stream function interpolated with the SPH kernel: membranes "
      "keep their area), bspline (the same curl, the stream function interpolated by tensor cubic B-splines on the "
      "lattice: no lattice-scale ripple), spreading_kernel (the same curl, the SPH kernel of the membranes' "
      "spreading radius membrane.h_star: as wide as the spreading at any h*; the free membranes share one h_star), "
      "sph (the paper's normalised SPH interpolation, Eq. 63); auto: for eulerian "
      "bspline when a membrane has bending or a law other than hookean, else divergence_free; sph for the other "
      "methods");
  if ((interp == "divergence_free" || interp == "bspline" || interp == "spreading_kernel") &&
      s.method != FluidMethod::Eulerian)
    r.fail("coupling.interpolation", "\"" + interp + "\" needs method \"eulerian\" (the fixed lattice's stream function)");
  s.sim.interpolation = interp == "divergence_free" ? MarkerInterpolation::DivergenceFree
                        : interp == "bspline"       ? MarkerInterpolation::BSpline
                        : interp == "sph"           ? MarkerInterpolation::Sph
                        : interp == "spreading_kernel" ? MarkerInterpolation::SpreadingKernel
                                                    : MarkerInterpolation::Auto;
}

// What is written and observed.
void read_output(Reader& r, Scene& s) {
  s.output_interval = r.number("output.interval", 0.0, ">= 0", "time between HDF5 snapshots (0: first and last only)", false, 0.0);
  s.checkpoint_interval = r.number("output.checkpoint_interval", 0.0, ">= 0",
                                   "time between checkpoints, DIR/checkpoint.h5 (0: only at the end)", false, 0.0);
  s.diagnostics_every = r.integer("output.diagnostics_every", 0, 0, "steps between diagnostics rows (0: about 500 rows per run)");
  if (const toml::node* ts = r.raw("output.times", "array of numbers", "snapshot times besides output.interval's (each at the step nearest it)")) {
    const toml::array* a = ts->as_array();
    if (!a) r.fail("output.times", "must be an array of numbers");
    for (const auto& e : *a) {
      const auto v = e.value<double>();
      if (!v || !std::isfinite(*v) || *v < 0) r.fail("output.times", "each time must be a finite number >= 0");
      s.output_times.push_back(*v);
    }
  }
  if (const toml::node* fl = r.raw("output.fields", "array of strings", "particle fields in snapshots, from u, v, p, phi, surface (1 on the free surface)")) {
    const toml::array* a = fl->as_array();
    if (!a) r.fail("output.fields", "must be an array of strings");
    s.fields.clear();
    for (const auto& e : *a) {
      const auto v = e.value<std::string>();
      if (!v || (*v != "u" && *v != "v" && *v != "p" && *v != "phi" && *v != "surface"))
        r.fail("output.fields", "allowed field names: u, v, p, phi, surface");
      if (std::find(s.fields.begin(), s.fields.end(), *v) != s.fields.end())
        r.fail("output.fields", "\"" + *v + "\" is listed twice");
      s.fields.push_back(*v);
    }
  }
  s.exact = r.choice("observe.exact", "none",
                     {"none", "poiseuille", "couette", "cavity", "membrane_equilibrium", "membrane_oscillation",
                      "inclined_plane", "droplet", "dam_break"},
                     "which exact or reference solution to measure against (inclined_plane, droplet, dam_break: "
                     "Afanasiev et al. Sections 6.2, 6.3, 7)");
  s.loads = r.boolean("observe.loads", false,
                      "the pressure force on every wall and its change since t = 0, the load of Afanasiev et al. Eq. (31): "
                      "columns force_<wall>, load_<wall>; on the fixed lattice (eulerian) also the fluid's shear stress at "
                      "every wall, shear_<wall>, and with sliding bottom and top walls the effective viscosity mu_eff "
                      "(their mean shear stress over the walls' shear rate)");
  s.reference_dir = r.text("observe.reference_dir", "reference", "directory of the Ghia et al. tables, relative to the scene file");
  s.memory_limit_gb = r.number("limits.memory_gb", 0.0, ">= 0",
                               "refuse a run whose memory estimate (sphib check) exceeds this many GB (0: the machine's "
                               "memory, MemTotal or the cgroup's limit); raise it to run anyway",
                               false, 0.0);
  s.threads = static_cast<int>(std::min<long>(
      r.machine_default("limits.threads", 1, "OMP_NUM_THREADS, else the cores not busy at the start",
                        "threads the step's passes and lattice solves share (OpenMP; results do not depend on the count; "
                        "the command line's --threads sets it too)"),
      1024));
}

// Pressure probes on the walls (observe/probes.cpp): observe.probes, probe_names, probe_size,
// probe_window. A probe must lie on a wall line, within the wall.
void read_probes(Reader& r, Scene& s) {
  const Domain& d = s.sim.fluid.domain;
  ProbeParams& pp = s.probes;
  std::vector<std::string> names;
  if (const toml::node* n = r.raw("observe.probe_names", "array of strings",
                                  "names of the probes, one per observe.probes entry (default 1, 2, ...): columns probe_<name>")) {
    const toml::array* a = n->as_array();
    if (!a) r.fail("observe.probe_names", "must be an array of strings");
    for (const auto& e : *a) {
      const auto v = e.value<std::string>();
      if (!v || v->empty() || v->find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_") != std::string::npos)
        r.fail("observe.probe_names", "each name must be a non-empty word of letters, digits and _");
      if (std::find(names.begin(), names.end(), *v) != names.end()) r.fail("observe.probe_names", "\"" + *v + "\" is listed twice");
      names.push_back(*v);
    }
  }
  if (const toml::node* n = r.raw("observe.probes", "array of [x, y]",
                                  "pressure probes: points on wall lines (e.g. [[1.61, 0.003]] on the right wall x = 1.61); "
                                  "columns probe_<name>, the pressure a sensor of width observe.probe_size reads, averaged over "
                                  "observe.probe_window (observe/probes.cpp)")) {
    const toml::array* a = n->as_array();
    if (!a) r.fail("observe.probes", "must be an array of [x, y] points");
    const double tol = 1e-9 * std::max(d.Lx(), d.Ly());
    for (size_t k = 0; k < a->size(); ++k) {
      const toml::array* pt = a->get(k)->as_array();
      Eigen::Vector2d x;
      if (!pt || pt->size() != 2) r.fail("observe.probes", "entry " + std::to_string(k) + " must be [x, y]");
      for (int c = 0; c < 2; ++c) {
        const auto v = pt->get(c)->value<double>();
        if (!v || !std::isfinite(*v)) r.fail("observe.probes", "entry " + std::to_string(k) + " must hold two finite numbers");
        x[c] = *v;
      }
      PressureProbe pr;
      pr.x = x;
      pr.name = k < names.size() ? names[k] : std::to_string(k + 1);
      bool on_wall = false;
      for (Side side : {Left, Right, Bottom, Top}) {
        const bool vertical = side == Left || side == Right;
        const double line = side == Left ? d.x0 : side == Right ? d.x1 : side == Bottom ? d.y0 : d.y1;
        const double across = vertical ? x.x() : x.y(), along = vertical ? x.y() : x.x();
        const double lo = vertical ? d.y0 : d.x0, hi = vertical ? d.y1 : d.x1;
        if (d.is_wall(side) && std::fabs(across - line) <= tol && along >= lo - tol && along <= hi + tol) {
          pr.side = side;
          on_wall = true;
          break;
        }
      }
      if (!on_wall) {
        std::ostringstream m;
        m << "entry " << k << " [" << x.x() << ", " << x.y() << "] is not on a wall of the tank [" << d.x0 << ", " << d.x1
          << "] x [" << d.y0 << ", " << d.y1 << "] (a probe is a point of a wall line)";
        r.fail("observe.probes", m.str());
      }
      pp.probes.push_back(pr);
    }
    if (!names.empty() && names.size() != pp.probes.size())
      r.fail("observe.probe_names", "must name every probe (" + std::to_string(pp.probes.size()) + " in observe.probes)");
  } else if (!names.empty()) {
    r.fail("observe.probe_names", "names probes, but observe.probes lists none");
  }
  pp.size = r.number("observe.probe_size", 0.0, ">= 0",
                     "a probe's sensor width along its wall (its reading is the mean pressure over it; 0: a point)", false, 0.0);
  pp.window = r.number("observe.probe_window", 0.0, ">= 0",
                       "a probe's averaging time: each reading is the mean over the steps of [t - window, t] (0: the step's own)",
                       false, 0.0);
}

// [membrane] for one, [[membranes]] for several (documenting: the keys of [membrane] are listed).
void read_membranes(Reader& r, Scene& s, bool documenting) {
  if (r.has("membrane") && r.has("membranes")) r.fail("membranes", "give either [membrane] or [[membranes]], not both");
  if (r.has("membrane") || documenting) {
    if (r.has("membrane") && !r.find("membrane")->is_table()) r.fail("membrane", "must be a table");
    MembraneScene m;
    read_membrane(r, "membrane.", m);
    if (r.has("membrane")) s.membranes.push_back(m);
  }
  if (const toml::node* arr = r.raw("membranes", "array of tables", "several membranes, each with the keys of [membrane]")) {
    const toml::array* a = arr->as_array();
    if (!a || !a->is_array_of_tables()) r.fail("membranes", "must be an array of tables [[membranes]]");
    for (size_t k = 0; k < a->size(); ++k) {
      MembraneScene m;
      read_membrane(r, "membranes[" + std::to_string(k) + "].", m);
      s.membranes.push_back(m);
    }
  }
}

// [contact]: the short-range repulsion between membranes and off the walls (coupling/contact.hpp).
void read_contact(Reader& r, Scene& s, size_t program_membranes, bool more_may_follow) {
  ContactParams& c = s.sim.contact;
  c.strength = r.number("contact.strength", 0.0, ">= 0",
                        "De of the Morse repulsion between the line elements of different membranes (and off the walls), "
                        "an energy per unit length of each: 0 turns the contact force off",
                        false, 0.0);
  c.range = r.number("contact.range", 0.0, ">= 0",
                     "r0: the repulsion acts between markers closer than this (0: two lattice spacings, 2 min(dx, dy))",
                     false, 0.0);
  c.beta = r.number("contact.beta", 0.0, ">= 0", "the potential's steepness beta, 1/length (0: 2/range)", false, 0.0);
  c.walls = r.boolean("contact.walls", true, "the walls push markers off too (a flat membrane's push along the wall line)");
  if (r.documenting) return;
  const FluidParams& f = s.sim.fluid;
  const double dx = f.domain.Lx() / f.nx, dy = f.domain.Ly() / f.ny;
  if (c.range == 0.0) c.range = 2.0 * std::min(dx, dy);
  const Domain& d = f.domain;
  if ((d.periodic_x && !(3.0 * c.range < d.Lx())) || (d.periodic_y && !(3.0 * c.range < d.Ly())))
    r.fail("contact.range", "value " + fmt_num(c.range) + " must be below a third of the periodic period");
  const bool walls = c.walls && !(d.periodic_x && d.periodic_y);
  const size_t n = s.membranes.size() + program_membranes;  // the file's and a program's
  if (c.strength > 0 && !more_may_follow && (n == 0 || (n == 1 && !walls)))
    r.fail("contact.strength", "acts between membranes and off walls: this scene has " + std::to_string(n) +
                                   " membrane(s)" + (walls ? "" : " and no wall to push off"));
}

// membrane.semi_implicit as given, else its default: with bending or a law other than hookean.
bool program_semi_implicit(const ProgramMembrane& m) {
  return m.semi_implicit.value_or(m.membrane.mat.Eb > 0 || m.membrane.mat.law != "hookean");
}

// A program's membrane's values, by the rules of a file's keys ("" when they pass): the key and why.
std::pair<std::string, std::string> program_membrane_problem(const ProgramMembrane& m, const std::string& p) {
  const Membrane& mb = m.membrane;
  if (mb.nb() < 4 || mb.nb() > kMaxMarkers)
    return {p + "nb", "value " + std::to_string(mb.nb()) + " is out of range (allowed: [4, " + std::to_string(kMaxMarkers) + "])"};
  if (!std::isfinite(mb.L0()) || !(mb.L0() > 0)) return {p + "r0", "value " + fmt_num(mb.L0() / (2 * M_PI)) + " is out of range (allowed: > 0)"};
  const std::string modulus = p + (mb.mat.law == "hookean" ? "T0" : "Es");
  if (!std::isfinite(mb.mat.Es)) return {modulus, "must be finite (got " + fmt_num(mb.mat.Es) + ")"};
  if (!(mb.mat.Es >= 0)) return {modulus, "value " + fmt_num(mb.mat.Es) + " is out of range (allowed: >= 0)"};
  if (!std::isfinite(mb.mat.Eb) || !(mb.mat.Eb >= 0)) return {p + "Eb", "value " + fmt_num(mb.mat.Eb) + " is out of range (allowed: >= 0)"};
  if (!(m.viscosity_ratio >= 0.01 && m.viscosity_ratio <= 100))
    return {p + "viscosity_ratio", "value " + fmt_num(m.viscosity_ratio) + " is out of range (allowed: [0.01, 100])"};
  try {  // the law, its parameters, the reference: make_membrane's checks, named by key
    make_membrane(mb.X, mb.ref, mb.mat);
  } catch (const std::invalid_argument& e) {
    const std::string why = e.what();
    const std::string key = why.find("law") != std::string::npos ? "law" : why.find(" C ") != std::string::npos ? "C" : "reference";
    return {p + key, why};
  }
  if (!mb.X.allFinite()) return {p + "points", "each point must be two finite numbers"};
  if (!std::isfinite(m.h_star) || !(m.h_star >= 0)) return {p + "h_star", "value " + fmt_num(m.h_star) + " is out of range (allowed: >= 0)"};
  if (!std::isfinite(m.h_star_over_h) || !(m.h_star_over_h > 0))
    return {p + "h_star_over_h", "value " + fmt_num(m.h_star_over_h) + " is out of range (allowed: > 0)"};
  if (m.stiff_residual && !program_semi_implicit(m))
    return {p + "stiff_residual", "refines the semi-implicit force: set semi_implicit = true too"};
  return {};
}

// A membrane's tension cutoff unless given: 2 lattice spacings for the inextensible penalty, whose
// stretching modes shorter than the lattice carries it destabilises (docs/membrane_validation.md); none otherwise.
double default_tension_cutoff(const std::string& law, double dx, double dy) {
  return law == "inextensible" ? 2.0 * std::max(dx, dy) : 0.0;
}

// The membranes, built in the domain's coordinates, then a program's (checked as a file's).
void build_membranes(Reader& r, Scene& s, const std::vector<ProgramMembrane>& program) {
  const FluidParams& f = s.sim.fluid;
  const double dx = (f.domain.x1 - f.domain.x0) / f.nx, dy = (f.domain.y1 - f.domain.y0) / f.ny;
  const double h = f.h_over_dx * 0.5 * (dx + dy);
  for (size_t k = 0; k < s.membranes.size(); ++k) {
    const MembraneScene& m = s.membranes[k];
    const std::string p = s.membranes.size() == 1 && r.has("membrane") ? "membrane." : "membranes[" + std::to_string(k) + "].";
    MembraneSetup setup;
    try {
      const Mat2 X = m.shape == "circle"    ? circle(m.nb, m.cx, m.cy, m.radius)
                     : m.shape == "ellipse" ? (m.spacing == "arclength" ? ellipse_by_arclength(m.nb, m.cx, m.cy, m.rx, m.ry)
                                                                        : ellipse(m.nb, m.cx, m.cy, m.rx, m.ry))
                                            : from_points(m.points, m.nb);
      Material mat;
      mat.law = m.law;
      mat.Es = m.Es;
      mat.params = m.law_params;
      mat.Eb = m.Eb;
      mat.spontaneous = m.spontaneous;
      mat.spontaneous_curvature = m.kappa0;
      mat.tension_cutoff = m.tension_cutoff >= 0.0 ? m.tension_cutoff : default_tension_cutoff(m.law, dx, dy);
      setup.membrane = make_membrane(X, m.reference == "circle" ? circle_reference(m.r0) : initial_reference(X, m.prestretch),
                                     mat);
    } catch (const std::invalid_argument& e) {
      r.fail(p + "shape", e.what());
    }
    setup.h_star = m.h_star > 0 ? m.h_star : m.h_star_over_h * h;
    setup.fixed = m.fixed;
    setup.semi_implicit = m.semi_implicit;
    setup.stiff_residual = m.stiff_residual;
    setup.viscosity_ratio = m.viscosity_ratio;
    if (m.viscosity_ratio != 1.0 && s.method != FluidMethod::Eulerian)
      r.fail(p + "viscosity_ratio", "a viscosity contrast needs method \"eulerian\" (method \"" + std::string(to_string(s.method)) +
                                        "\" has one viscosity everywhere)");
    s.sim.membranes.push_back(setup);
  }
  for (const ProgramMembrane& m : program) {
    const std::string p = "membranes[" + std::to_string(s.sim.membranes.size()) + "].";
    if (const auto [key, why] = program_membrane_problem(m, p); !key.empty()) r.fail(key, why);
    if (m.viscosity_ratio != 1.0 && s.method != FluidMethod::Eulerian)
      r.fail(p + "viscosity_ratio", "a viscosity contrast needs method \"eulerian\" (method \"" + std::string(to_string(s.method)) +
                                        "\" has one viscosity everywhere)");
    if (m.tension_cutoff && !(*m.tension_cutoff >= 0.0 && std::isfinite(*m.tension_cutoff)))
      r.fail(p + "tension_cutoff", "value " + fmt_num(*m.tension_cutoff) + " is out of range (allowed: >= 0)");
    Membrane mb = m.membrane;
    mb.mat.tension_cutoff = m.tension_cutoff                ? *m.tension_cutoff
                            : mb.mat.tension_cutoff > 0.0 ? mb.mat.tension_cutoff
                                                          : default_tension_cutoff(mb.mat.law, dx, dy);
    s.sim.membranes.push_back({std::move(mb), m.h_star > 0 ? m.h_star : m.h_star_over_h * h, m.fixed, program_semi_implicit(m),
                               m.viscosity_ratio, m.stiff_residual});
  }
  size_t second = 0;
  if (const std::string why = membranes_cross(s.sim.membranes, s.sim.fluid.domain, nullptr, &second); !why.empty())
    r.fail(second < s.membranes.size() && s.membranes.size() == 1 && r.has("membrane") ? "membrane"  // the file's one
                                                                                         : "membranes[" + std::to_string(second) + "]",
           why);
}

Scene build(toml::table& root, const std::string& name, const std::set<std::string>& overridden,
            std::vector<Reader::Doc>* docs_out, const std::vector<ProgramMembrane>& program = {}, bool more_may_follow = false) {
  if (!docs_out) reject_unknown_keys(root, "", known_keys(), name, overridden);
  Reader r(root, name, overridden);
  r.documenting = docs_out != nullptr;
  Scene s;
  s.path = name;
  s.title = r.text("title", "", "a one-line description");
  // A new method is added here, to make_fluid and, with a free surface, to supports_free_surface
  // (fluid/common/free_surface.cpp).
  s.method = r.option("method", FluidMethod::Eulerian, kFluidMethods,
                      "fluid solver: eulerian (EPSPH, fixed particles), lagrangian (LPSPH, moving particles), "
                      "wcsph (weakly compressible SPH), isph (incompressible SPH with a free surface, Afanasiev et al. "
                      "2011)");
  read_domain(r, s);
  read_fluid(r, s);
  read_free_surface(r, s);
  read_regularisation(r, s);
  read_gate(r, s);
  read_time_and_solvers(r, s);
  read_output(r, s);
  read_probes(r, s);
  read_membranes(r, s, docs_out != nullptr);
  read_contact(r, s, program.size(), more_may_follow);
  if (docs_out) { *docs_out = r.docs; return s; }
  r.reject_unknown();
  s.resolved = r.resolved;
  if (const auto e = free_surface_problem(s.sim.fluid)) r.fail(e->key, e->what);
  if (const std::string why = fill_leaves_no_surface(s.sim.fluid); !why.empty()) r.fail("fill.shape", why);
  if ((!s.membranes.empty() || !program.empty()) && has_free_surface(s.sim.fluid.domain, s.sim.fluid.free_surface))
    r.fail(r.has("membrane") ? "membrane" : "membranes", "membranes in a free-surface scene are not supported");

  if (const std::string why = steps_problem(s); !why.empty()) r.fail("time.end", why);
  build_membranes(r, s, program);
  if (more_may_follow && s.sim.membranes.empty()) return s;  // observe.exact may wait for a membrane
  if (const std::string why = exact_cannot_apply(s); !why.empty()) r.fail("observe.exact", why);
  return s;
}

// Every key a scene may have, as `sphib keys` lists them (membrane.* stands for membranes[k].*).
const std::vector<std::string>& known_keys() {
  static const std::vector<std::string> keys = [] {
    toml::table empty;
    std::vector<Reader::Doc> docs;
    build(empty, "keys", {}, &docs);
    std::vector<std::string> k;
    for (const auto& d : docs) k.push_back(d.key);
    return k;
  }();
  return keys;
}

Scene from_table(toml::table root, const std::string& name, const std::vector<std::string>& overrides,
                 const std::vector<ProgramMembrane>& program = {}, bool more_may_follow = false) {
  std::set<std::string> overridden;
  for (const auto& kv : overrides) overridden.insert(apply_override(root, kv, name));
  return build(root, name, overridden, nullptr, program, more_may_follow);
}

// The cavity's Ghia tables are in observe.reference_dir (resolved against the scene file's folder).
void require_reference_tables(const Scene& s, const std::string& name) {
  std::error_code ec;
  const std::string table = s.reference_dir + "/ghia1982_u_vertical_centreline.csv";
  if (s.exact == "cavity" && !std::filesystem::is_regular_file(table, ec))
    throw SceneError(name + ": observe.reference_dir: " + s.reference_dir + " has no Ghia tables (" + table + ")");
}

// The type of a key as `sphib keys` lists it ("" if no scene has it).
std::string key_type(const std::string& key) {
  static const std::map<std::string, std::string> types = [] {
    toml::table empty;
    std::vector<Reader::Doc> docs;
    build(empty, "keys", {}, &docs);
    std::map<std::string, std::string> t;
    for (const auto& d : docs) t[d.key] = d.type;
    return t;
  }();
  const auto it = types.find(generic_key(key));
  return it == types.end() ? "" : it->second;
}

// Puts `value` at the dotted `key` of root (membranes[k] as the k-th table of the array).
void put(toml::table& root, const std::string& key, toml::node&& value, const std::string& name) {
  toml::table* t = &root;
  size_t start = 0;
  for (size_t dot = key.find('.'); dot != std::string::npos; start = dot + 1, dot = key.find('.', start)) {
    const std::string part = key.substr(start, dot - start);
    const size_t br = part.find('[');
    if (br == std::string::npos) {
      if (!t->contains(part)) t->insert(part, toml::table{});
      t = (*t)[part].as_table();
    } else {
      const std::string arr_name = part.substr(0, br);
      const long idx = std::strtol(part.c_str() + br + 1, nullptr, 10);
      if (!t->contains(arr_name)) t->insert(arr_name, toml::array{});
      toml::array* a = (*t)[arr_name].as_array();
      if (!a || idx < 0 || idx > 100000) t = nullptr;
      else {
        while (static_cast<long>(a->size()) <= idx) a->push_back(toml::table{});
        t = a->get(static_cast<size_t>(idx))->as_table();
      }
    }
    if (!t) throw SceneError(name + ": " + key + ": its place in the scene is not a table");
  }
  t->insert_or_assign(key.substr(start), std::move(value));
}

Scene parse_text(const std::string& text, const std::string& name, const std::vector<std::string>& overrides,
                 const std::vector<ProgramMembrane>& program, bool more_may_follow = false) {
  if (const auto [line, parts] = deepest_key(text); line > 0)
    throw SceneError(name + ":" + std::to_string(line) + ": a key of " + std::to_string(parts) +
                     " dotted parts (a scene's keys have a few; at most " + std::to_string(kMaxKeyParts) + ")");
  toml::table root;
  try {
    root = toml::parse(text, name);
  } catch (const toml::parse_error& e) {
    std::ostringstream m;
    m << name << ":" << e.source().begin.line << ": TOML syntax error: " << e.description();
    throw SceneError(m.str());
  }
  return from_table(std::move(root), name, overrides, program, more_may_follow);
}

Scene load_file(const std::string& path, const std::vector<std::string>& overrides,
                const std::vector<ProgramMembrane>& program, bool more_may_follow = false) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw SceneError(path + ": is a directory, not a scene file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SceneError(path + ": cannot read the scene file");
  // At most kMaxSceneBytes (+1 to notice more): /dev/zero or a wrong file is refused, not read into memory.
  constexpr std::streamsize kMaxSceneBytes = 16 << 20;
  std::string text(kMaxSceneBytes + 1, '\0');
  in.read(text.data(), kMaxSceneBytes + 1);
  if (in.bad()) throw SceneError(path + ": cannot read the scene file");
  if (in.gcount() > kMaxSceneBytes) throw SceneError(path + ": larger than 16 MB: not a scene file");
  text.resize(static_cast<size_t>(in.gcount()));
  Scene s = parse_text(text, path, overrides, program, more_may_follow);
  s.reference_dir = (fs::path(path).parent_path() / s.reference_dir).string();
  require_reference_tables(s, path);
  return s;
}

}  // namespace

Scene scene_from_values(const std::vector<std::pair<std::string, std::string>>& values, const std::string& name,
                        const std::vector<std::string>& overrides, const std::string& base_dir) {
  toml::table root;
  for (const auto& [k, v] : values) {
    if (restates_other_keys(k)) continue;
    // A wall velocity is recorded for every side; at rest it is what its absence means (and on a
    // periodic or open side, only its absence is allowed).
    if (k.rfind("walls.", 0) == 0 && v == "[0, 0]") continue;
    const std::string type = key_type(k);
    if (type.empty()) throw SceneError(name + ": " + k + ": not a scene key of this sphib");
    if (type == "string") {
      put(root, k, toml::value<std::string>(v), name);
      continue;
    }
    toml::table parsed;
    try {
      parsed = toml::parse("v = " + v);
    } catch (const toml::parse_error&) {
      throw SceneError(name + ": " + k + ": the value " + v + " does not read back as TOML");
    }
    if (parsed.size() != 1 || !parsed.get("v")) throw SceneError(name + ": " + k + ": the value " + v + " is not one value");
    put(root, k, std::move(*parsed.get("v")), name);
  }
  Scene s = from_table(std::move(root), name, overrides);
  s.reference_dir = (std::filesystem::path(base_dir) / s.reference_dir).string();
  require_reference_tables(s, name);
  return s;
}

bool restates_other_keys(const std::string& key) { return key == "membranes"; }

std::string scene_hash(const Scene& s) {
  std::string text;
  for (const auto& [k, v] : s.resolved)
    if (!restates_other_keys(k)) text += std::to_string(k.size()) + ":" + k + "=" + std::to_string(v.size()) + ":" + v + "\n";
  return sha256_hex(text);
}


Scene parse_scene(const std::string& text, const std::string& name, const std::vector<std::string>& overrides) {
  return parse_text(text, name, overrides, {});
}

Scene load_scene(const std::string& path, const std::vector<std::string>& overrides) {
  return load_file(path, overrides, {});
}

Scene build_scene(const std::string& path, const std::string& name, const std::vector<std::string>& overrides,
                  const std::vector<ProgramMembrane>& membranes, bool more_may_follow) {
  return path.empty() ? parse_text("", name, overrides, membranes, more_may_follow)
                      : load_file(path, overrides, membranes, more_may_follow);
}

std::string describe_scene_keys() {
  toml::table empty;
  std::vector<Reader::Doc> docs;
  build(empty, "keys", {}, &docs);
  std::ostringstream o;
  for (const auto& d : docs) {
    auto esc = [](std::string t) {  // a '|' inside a Markdown table cell
      for (size_t k = t.find('|'); k != std::string::npos; k = t.find('|', k + 2)) t.replace(k, 1, "\\|");
      return t;
    };
    o << "| `" << d.key << "` | " << esc(d.type) << " | " << esc(d.def) << " | " << esc(d.range) << " | "
      << esc(d.what) << " |\n";
  }
  return o.str();
}

std::string scene_keys_json() {
  toml::table empty;
  std::vector<Reader::Doc> docs;
  build(empty, "keys", {}, &docs);
  // A default as its TOML text ("1.2", "true", "\"auto\"", "[0, 1]") -> the JSON value of that type.
  auto value = [](const std::string& def) -> nlohmann::json {
    if (def.empty() || def == "(required)") return nullptr;
    toml::table t;
    try {
      t = toml::parse("v = " + def);
    } catch (const toml::parse_error&) {
      return def;
    }
    std::function<nlohmann::json(const toml::node&)> to_json = [&](const toml::node& n) -> nlohmann::json {
      if (const auto* a = n.as_array()) {
        nlohmann::json j = nlohmann::json::array();
        for (const auto& e : *a) j.push_back(to_json(e));
        return j;
      }
      if (n.is_boolean()) return n.as_boolean()->get();
      if (n.is_integer()) return n.as_integer()->get();
      if (n.is_floating_point()) return n.as_floating_point()->get();
      if (n.is_string()) return n.as_string()->get();
      return nullptr;
    };
    return to_json(*t.get("v"));
  };
  nlohmann::json out = nlohmann::json::array();
  for (const auto& d : docs)
    out.push_back({{"name", d.key}, {"type", d.type}, {"default", value(d.def)}, {"required", d.def == "(required)"},
                   {"range", d.range}, {"help", d.what}});
  return out.dump(1) + "\n";
}

}  // namespace sphib

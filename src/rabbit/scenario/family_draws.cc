#include "rabbit/scenario/family_draws.h"

#include <cctype>
#include <cmath>
#include <cstdlib>

#include "rabbit/io/toml_reader.h"
#include "rabbit/scenario/suite.h"

namespace rabbit {
namespace {

constexpr long kMaxChanges = 100;  // velocity.changes count
constexpr size_t kMaxExpressionChars = 400;

// A recursive-descent parser over the text of one expression.
class Parser {
 public:
  Parser(const std::string& text, const std::map<std::string, double>& names)
      : text_(text), names_(names) {}

  bool Parse(double* value, std::string* error) {
    if (text_.size() > kMaxExpressionChars) {
      *error = "an expression of at most " + std::to_string(kMaxExpressionChars) + " characters";
      return false;
    }
    *value = Sum();
    Skip();
    if (error_.empty() && pos_ < text_.size()) Error("unexpected '" + text_.substr(pos_, 1) + "'");
    if (error_.empty() && !std::isfinite(*value)) Error("the value is not finite");
    if (!error_.empty()) {
      *error = "in \"=" + text_ + "\": " + error_;
      return false;
    }
    return true;
  }

 private:
  void Skip() {
    while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_]))) ++pos_;
  }
  bool Eat(char c) {
    Skip();
    if (pos_ < text_.size() && text_[pos_] == c) {
      ++pos_;
      return true;
    }
    return false;
  }
  void Error(const std::string& message) {
    if (error_.empty()) error_ = message;
  }
  double Sum() {
    double v = Product();
    while (error_.empty()) {
      if (Eat('+')) {
        v += Product();
      } else if (Eat('-')) {
        v -= Product();
      } else {
        break;
      }
    }
    return v;
  }
  double Product() {
    double v = Unary();
    while (error_.empty()) {
      if (Eat('*')) {
        v *= Unary();
      } else if (Eat('/')) {
        const double d = Unary();
        if (d == 0.0) Error("division by zero");
        v /= d;
      } else {
        break;
      }
    }
    return v;
  }
  double Unary() {
    if (++depth_ > 100) {
      Error("nested too deeply");
      return 0.0;
    }
    double v = 0.0;
    if (Eat('-')) {
      v = -Unary();
    } else if (Eat('+')) {
      v = Unary();
    } else {
      v = Atom();
    }
    --depth_;
    return v;
  }
  double Atom() {
    Skip();
    if (pos_ >= text_.size()) {
      Error("a number, a name or '(' expected at the end");
      return 0.0;
    }
    const char c = text_[pos_];
    if (c == '(') {
      ++pos_;
      const double v = Sum();
      if (!Eat(')')) Error("')' expected");
      return v;
    }
    if (std::isdigit(static_cast<unsigned char>(c)) || c == '.') {
      const char* begin = text_.c_str() + pos_;
      char* end = nullptr;
      const double v = std::strtod(begin, &end);
      if (end == begin) {
        Error("a bad number");
        return 0.0;
      }
      pos_ += static_cast<size_t>(end - begin);
      return v;
    }
    if (std::isalpha(static_cast<unsigned char>(c)) || c == '_') {
      const size_t start = pos_;
      while (pos_ < text_.size() &&
             (std::isalnum(static_cast<unsigned char>(text_[pos_])) || text_[pos_] == '_')) {
        ++pos_;
      }
      const std::string name = text_.substr(start, pos_ - start);
      const auto found = names_.find(name);
      if (found == names_.end()) {
        Error("'" + name + "' names no draw of the family");
        return 0.0;
      }
      return found->second;
    }
    Error("unexpected '" + std::string(1, c) + "'");
    return 0.0;
  }

  const std::string& text_;
  const std::map<std::string, double>& names_;
  size_t pos_ = 0;
  int depth_ = 0;
  std::string error_;
};

bool IsName(const std::string& s) {
  if (s.empty() || s.size() > 64 ||
      !(std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_')) {
    return false;
  }
  for (const char c : s) {
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) return false;
  }
  return true;
}

// [low, high] from an array of two numbers, or one number (low = high); in the table `t`.
DrawRange ReadPair(TomlReader* t, const std::string& key) {
  DrawRange r;
  if (t->IsArray(key)) {
    const std::vector<double> v = t->Doubles(key, {}, 2);
    r.low = v[0];
    r.high = v[1];
  } else {
    r.low = r.high = t->RequiredDouble(key);
  }
  if (!(r.low <= r.high)) t->Fail(key, "expected [low, high] with low <= high");
  return r;
}

// A range entry: [low, high] or { range = [low, high], random_sign, integer }.
DrawRange ReadRange(TomlReader* t, const std::string& key, const toml::node& node) {
  if (!node.is_table()) {
    const std::vector<double> v = t->Doubles(key, {}, 2);
    if (!(v[0] <= v[1])) t->Fail(key, "expected [low, high] with low <= high");
    return DrawRange{v[0], v[1], false, false};
  }
  TomlReader sub = t->Table(key);
  if (!sub.Has("range")) sub.Fail("range", "missing required key 'range'");
  const std::vector<double> v = sub.Doubles("range", {}, 2);
  if (!(v[0] <= v[1])) sub.Fail("range", "expected [low, high] with low <= high");
  DrawRange r{v[0], v[1], sub.Bool("random_sign", false), sub.Bool("integer", false)};
  if (r.integer && (std::floor(r.low) != r.low || std::floor(r.high) != r.high ||
                    std::abs(r.low) > 1e9 || std::abs(r.high) > 1e9)) {
    sub.Fail("range", "an integer draw needs whole-number bounds within +-1e9");
  }
  sub.Finish();
  return r;
}

// Reads one entry of [family.draw] or [family.vary] (not velocity.changes) into *spec, checking an
// expression's names against `known`.
void ReadEntry(TomlReader* t, const std::string& key, const toml::node& node,
               const std::map<std::string, double>& known, DrawSpec* spec) {
  spec->name = key;
  if (node.is_string()) {
    const std::string text = t->String(key, "");
    if (text.empty() || text[0] != '=') {
      t->Fail(key, "a string here is an expression starting with '=', e.g. \"=v_d * 2\"");
    }
    spec->expression = text.substr(1);
    double value = 0.0;
    std::string error;
    std::map<std::string, double> probe = known;  // names only: any value but 0 (division)
    for (auto& [name, v] : probe) v = 1.0;
    if (!EvaluateDrawExpression(spec->expression, probe, &value, &error) &&
        error.find("division by zero") == std::string::npos &&
        error.find("not finite") == std::string::npos) {
      t->Fail(key, error);
    }
    return;
  }
  if (!node.is_array() && !node.is_table()) {
    t->Fail(key, "expected [low, high], { range = [low, high], ... } or \"=expression\"");
  }
  spec->range = ReadRange(t, key, node);
}

double Draw(std::uint64_t seed, int member, const std::string& key, const DrawRange& r) {
  double value = 0.0;
  if (r.integer) {
    value = std::floor(FamilyDraw(seed, member, key, r.low, r.high + 1.0));
    value = std::min(value, r.high);
  } else {
    value = FamilyDraw(seed, member, key, r.low, r.high);
  }
  if (r.random_sign && FamilyDraw(seed, member, key + "#sign", 0.0, 1.0) < 0.5) value = -value;
  return value;
}

}  // namespace

bool EvaluateDrawExpression(const std::string& text, const std::map<std::string, double>& names,
                            double* value, std::string* error) {
  Parser parser(text, names);
  return parser.Parse(value, error);
}

FamilyDrawSpec ReadFamilyDrawSpec(TomlReader* draw, TomlReader* vary) {
  FamilyDrawSpec spec;
  // Every draw's name first: an expression may use any other draw (TOML tables have no order).
  std::map<std::string, double> all;
  for (const toml::table* layer : draw->layers()) {
    for (const auto& [key, node] : *layer) {
      const std::string k(key.str());
      if (!IsName(k)) {
        draw->Fail(k, "a draw's name is letters, digits and '_', starting with a letter or '_'");
      }
      if (k == "changes_end_s") draw->Fail(k, "the name changes_end_s is velocity.changes'");
      all[k] = 0.0;
    }
  }
  std::vector<DrawSpec> pending;  // expressions, until the draws they use are placed
  std::map<std::string, double> placed;
  for (const toml::table* layer : draw->layers()) {
    for (const auto& [key, node] : *layer) {
      const std::string k(key.str());
      if (placed.count(k) != 0) continue;  // a lower layer's duplicate: the first layer wins
      bool seen = false;
      for (const DrawSpec& d : pending) seen |= d.name == k;
      if (seen) continue;
      std::map<std::string, double> others = all;
      others.erase(k);
      DrawSpec d;
      ReadEntry(draw, k, node, others, &d);
      if (d.expression.empty()) {
        placed[k] = 0.0;
        spec.draws.push_back(d);
      } else {
        pending.push_back(d);
      }
    }
  }
  // Expressions in an order where each comes after the draws it uses.
  while (!pending.empty()) {
    bool progress = false;
    for (size_t i = 0; i < pending.size();) {
      double value = 0.0;
      std::string error;
      std::map<std::string, double> probe = placed;
      for (auto& [name, v] : probe) v = 1.0;
      const bool ok = EvaluateDrawExpression(pending[i].expression, probe, &value, &error);
      if (ok || error.find("names no draw") == std::string::npos) {
        placed[pending[i].name] = 0.0;
        spec.draws.push_back(pending[i]);
        pending.erase(pending.begin() + static_cast<std::ptrdiff_t>(i));
        progress = true;
      } else {
        ++i;
      }
    }
    if (!progress) {
      draw->Fail(pending.front().name, "the draws' expressions use each other in a circle");
    }
  }
  draw->Finish();
  std::map<std::string, double>& known = placed;
  for (const toml::table* layer : vary->layers()) {
    const toml::node* changes = layer->get("velocity.changes");
    if (changes == nullptr || spec.changes.present) continue;
    if (!changes->is_table()) {
      vary->Fail("velocity.changes",
                 "expected a table { count = [3, 5], every_s = [6, 10], v = [0.3, 1.0] }");
    }
    TomlReader c = vary->Table("velocity.changes");
    VelocityChanges& vc = spec.changes;
    vc.present = true;
    for (const char* required : {"count", "every_s", "v"}) {
      if (!c.Has(required))
        c.Fail(required, std::string("missing required key '") + required + "'");
    }
    vc.count = ReadPair(&c, "count");
    if (std::floor(vc.count.low) != vc.count.low || std::floor(vc.count.high) != vc.count.high ||
        vc.count.low < 0 || vc.count.high > kMaxChanges) {
      c.Fail("count", "whole numbers in [0, " + std::to_string(kMaxChanges) + "]");
    }
    vc.count.integer = true;
    vc.every_s = ReadPair(&c, "every_s");
    if (!(vc.every_s.low > 0.0)) c.Fail("every_s", "hold times must be > 0 s");
    vc.v = ReadPair(&c, "v");
    if (!(vc.v.low > 0.0 && vc.v.high < 3.0)) c.Fail("v", "velocities in (0, 3) m/s");
    vc.has_first = c.Has("first_s");
    if (vc.has_first) {
      vc.first_s = ReadPair(&c, "first_s");
      if (!(vc.first_s.low > 0.0)) c.Fail("first_s", "the first change comes after t = 0: > 0 s");
    }
    vc.has_ramp = c.Has("ramp_s");
    if (vc.has_ramp) {
      vc.ramp_s = ReadPair(&c, "ramp_s");
      if (!(vc.ramp_s.low > 0.0)) c.Fail("ramp_s", "ramp times must be > 0 s");
    }
    c.Finish();
  }
  if (spec.changes.present) known["changes_end_s"] = 0.0;
  std::map<std::string, bool> seen;
  for (const toml::table* layer : vary->layers()) {
    for (const auto& [key, node] : *layer) {
      const std::string k(key.str());
      if (k == "velocity.changes" || seen[k]) continue;
      seen[k] = true;
      if (k == "name" || k == "seed" || k.rfind("name.", 0) == 0 || k.rfind("seed.", 0) == 0) {
        vary->Fail(k, "a family member's name and seed are not varied (they come from the family)");
      }
      if (spec.changes.present && k.rfind("velocity.", 0) == 0) {
        vary->Fail(k, "velocity.changes writes the whole velocity profile: vary it there");
      }
      DrawSpec d;
      ReadEntry(vary, k, node, known, &d);
      spec.keys.push_back(d);
    }
  }
  vary->Finish();
  return spec;
}

bool DrawMember(const FamilyDrawSpec& spec, std::uint64_t family_seed, int member, MemberDraws* out,
                std::string* error, std::string* failed_key) {
  *out = MemberDraws();
  for (const DrawSpec& d : spec.draws) {
    double value = 0.0;
    if (d.expression.empty()) {
      value = Draw(family_seed, member, "draw:" + d.name, d.range);
    } else if (!EvaluateDrawExpression(d.expression, out->names, &value, error)) {
      *error = "draw '" + d.name + "' " + *error;
      return false;
    }
    out->names[d.name] = value;
    out->columns.emplace_back(d.name, value);
  }
  const VelocityChanges& vc = spec.changes;
  if (vc.present) {
    const std::string k = "velocity.changes#";
    const int count = static_cast<int>(Draw(family_seed, member, k + "count", vc.count));
    out->columns.emplace_back("velocity.changes.count", count);
    double v = Draw(family_seed, member, k + "v0", vc.v);
    out->columns.emplace_back("velocity.changes.v0", v);
    out->velocity_profile = vc.has_ramp ? "ramp" : "steps";
    out->velocity_points.emplace_back(0.0, v);
    double t = 0.0;
    for (int c = 1; c <= count; ++c) {
      const std::string n = std::to_string(c);
      const DrawRange& hold = c == 1 && vc.has_first ? vc.first_s : vc.every_s;
      t += Draw(family_seed, member, k + "t" + n, hold);
      const double next = Draw(family_seed, member, k + "v" + n, vc.v);
      out->columns.emplace_back("velocity.changes.t" + n, t);
      out->columns.emplace_back("velocity.changes.v" + n, next);
      if (vc.has_ramp) {
        // Hold the level until t, then ramp to the next one over the drawn ramp time.
        out->velocity_points.emplace_back(t, v);
        t += Draw(family_seed, member, k + "r" + n, vc.ramp_s);
        out->columns.emplace_back("velocity.changes.r" + n, t - out->velocity_points.back().first);
      }
      out->velocity_points.emplace_back(t, next);
      v = next;
    }
    out->names["changes_end_s"] = t;
  }
  for (const DrawSpec& d : spec.keys) {
    double value = 0.0;
    if (d.expression.empty()) {
      value = Draw(family_seed, member, d.name, d.range);
    } else if (!EvaluateDrawExpression(d.expression, out->names, &value, error)) {
      if (failed_key != nullptr) *failed_key = d.name;
      return false;
    }
    out->keys.emplace_back(d.name, value);
    out->columns.emplace_back(d.name, value);
  }
  return true;
}

}  // namespace rabbit

// The draws of a suite's randomised family (docs/formats/suite.md, "Families"): named draws shared
// by several keys, keys derived from them by arithmetic, and generated velocity profiles with a
// drawn number of changes. Every value comes from a hash of (the family's seed, the member's
// index, the draw's name): the same members on every machine, thread count or rank.
#ifndef RABBIT_SCENARIO_FAMILY_DRAWS_H_
#define RABBIT_SCENARIO_FAMILY_DRAWS_H_

#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace rabbit {

class TomlReader;

// Evaluates an arithmetic expression over named values: numbers, names ([A-Za-z_][A-Za-z0-9_]*),
// + - * /, unary minus and parentheses, with the usual precedence. Returns false with a message
// in *error for a syntax error, an unknown name or a result that is not finite.
bool EvaluateDrawExpression(const std::string& text, const std::map<std::string, double>& names,
                            double* value, std::string* error);

// One uniform range: [low, high], optionally with a random sign, optionally an integer in
// [low, high] (both ends included).
struct DrawRange {
  double low = 0.0, high = 0.0;
  bool random_sign = false;
  bool integer = false;
};

// A named draw of [family.draw] or a varied key of [family.vary]: a range, or an expression
// ("=expr") over the family's named draws.
struct DrawSpec {
  std::string name;  // the draw's name, or the key path
  DrawRange range;
  std::string expression;  // without its '='; empty: a range
};

// `velocity.changes` of [family.vary]: a generated V_d profile, one level held from t = 0, then
// `count` changes, each to a new drawn level after a drawn hold (and, with a ramp, over a drawn
// ramp time).
struct VelocityChanges {
  bool present = false;
  DrawRange count, every_s, v, first_s, ramp_s;
  bool has_first = false, has_ramp = false;
};

// A family's draw specification, read from its [family.draw] and [family.vary] tables.
struct FamilyDrawSpec {
  std::vector<DrawSpec> draws;  // [family.draw], in file order
  VelocityChanges changes;      // [family.vary] velocity.changes
  std::vector<DrawSpec> keys;   // [family.vary], the other keys in file order
};

// Reads them; InputError naming the file, line and key for a bad range or expression (the
// expressions' names are checked against the draws before them).
FamilyDrawSpec ReadFamilyDrawSpec(TomlReader* draw, TomlReader* vary);

// What one member drew.
struct MemberDraws {
  // Named draws (and changes_end_s) by name: the names expressions see.
  std::map<std::string, double> names;
  // The velocity profile's kind ("steps" or "ramp") and points, when velocity.changes is given.
  std::string velocity_profile;
  std::vector<std::pair<double, double>> velocity_points;
  // Every drawn or derived value by column (draws, velocity.changes.*, the varied keys), in the
  // spec's order: the member's row of members.csv.
  std::vector<std::pair<std::string, double>> columns;
  // The varied keys' values, in the spec's order.
  std::vector<std::pair<std::string, double>> keys;
};

// Draws member `member`'s values. Returns false with a message (naming the draw or the varied
// key and its expression) in *error when an expression cannot be evaluated (a division by zero,
// say); when it is a varied key's, that key goes to *failed_key (if given).
bool DrawMember(const FamilyDrawSpec& spec, std::uint64_t family_seed, int member, MemberDraws* out,
                std::string* error, std::string* failed_key = nullptr);

}  // namespace rabbit

#endif  // RABBIT_SCENARIO_FAMILY_DRAWS_H_

// Writing FLL (ToFll, SaveFll) and building the equivalent fuzzylite engine: the writing half of
// fll.h (fll.cc reads).
#include <fl/Headers.h>

#include <charconv>
#include <cmath>
#include <cstddef>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "rabbit/io/atomic_file.h"
#include "rabbit/io/csv.h"
#include "rabbit/io/error.h"
#include "rabbit/learn/fll.h"

namespace rabbit {
namespace {

std::string Number(double x) {
  if (std::isnan(x)) return "nan";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  char buffer[64];
  const std::to_chars_result result = std::to_chars(buffer, buffer + sizeof buffer, x);
  return std::string(buffer, result.ptr);
}

std::string TermText(const FuzzySet& set) {
  const Membership& m = set.membership;
  std::string text = set.name + " ";
  switch (m.shape) {
    case Membership::Shape::kTriangle:
      return text + "Triangle " + Number(m.a) + " " + Number(m.b) + " " + Number(m.c);
    case Membership::Shape::kTrapezoid:
      return text + "Trapezoid " + Number(m.a) + " " + Number(m.b) + " " + Number(m.c) + " " +
             Number(m.d);
    case Membership::Shape::kRampUp:
      return text + "Ramp " + Number(m.a) + " " + Number(m.b);
    case Membership::Shape::kRampDown:
      return text + "Ramp " + Number(m.b) + " " + Number(m.a);
    case Membership::Shape::kGaussian:
      return text + "Gaussian " + Number(m.a) + " " + Number(m.b);
  }
  throw std::invalid_argument("unknown membership shape");
}

std::string RuleText(const TsFis& fis, const FuzzyRule& rule) {
  std::string text = "if";
  for (std::size_t i = 0; i < fis.inputs.size(); ++i) {
    const FuzzyInput& input = fis.inputs[i];
    text += (i == 0 ? " " : " and ") + input.name + " is " +
            input.sets[static_cast<std::size_t>(rule.antecedent[i])].name;
  }
  return text + " then " + fis.output_name + " is " +
         fis.output_terms[static_cast<std::size_t>(rule.consequent)];
}

void RequireValid(const TsFis& fis, const char* what) {
  std::string why;
  if (!fis.IsValid(&why))
    throw std::invalid_argument(std::string(what) + ": invalid TsFis: " + why);
}

const char* Bool(bool value) { return value ? "true" : "false"; }

}  // namespace

std::string ToFll(const TsFis& fis, const std::string& comment) {
  RequireValid(fis, "ToFll");
  std::ostringstream out;
  if (!comment.empty()) {
    for (const std::string& line : SplitLines(comment)) {
      out << (line.empty() ? "#" : "# " + line) << '\n';
    }
  }
  out << "Engine: " << fis.name << '\n';
  for (const FuzzyInput& input : fis.inputs) {
    out << "InputVariable: " << input.name << '\n'
        << "  enabled: true\n"
        << "  range: " << Number(input.min) << ' ' << Number(input.max) << '\n'
        << "  lock-range: " << Bool(input.lock_range) << '\n';
    for (const FuzzySet& set : input.sets) out << "  term: " << TermText(set) << '\n';
  }
  out << "OutputVariable: " << fis.output_name << '\n'
      << "  enabled: true\n"
      << "  range: " << Number(fis.output_min) << ' ' << Number(fis.output_max) << '\n'
      << "  lock-range: " << Bool(fis.lock_output_range) << '\n'
      << "  aggregation: none\n"
      << "  defuzzifier: WeightedAverage TakagiSugeno\n"
      << "  default: " << Number(fis.default_value) << '\n'
      << "  lock-previous: false\n";
  for (std::size_t k = 0; k < fis.output_terms.size(); ++k) {
    out << "  term: " << fis.output_terms[k] << " Constant " << Number(fis.output_values[k])
        << '\n';
  }
  out << "RuleBlock: rules\n"
      << "  enabled: true\n"
      << "  conjunction: AlgebraicProduct\n"
      << "  disjunction: none\n"
      << "  implication: none\n"
      << "  activation: General\n";
  for (const FuzzyRule& rule : fis.rules) out << "  rule: " << RuleText(fis, rule) << '\n';
  return out.str();
}

void SaveFll(const TsFis& fis, const std::string& path, const std::string& comment) {
  const std::string text = ToFll(fis, comment);
  WriteFileAtomically(path, [&text](std::ostream& out) { out << text; });
}

std::unique_ptr<fl::Engine> MakeFuzzyliteEngine(const TsFis& fis) {
  RequireValid(fis, "MakeFuzzyliteEngine");
  auto engine = std::make_unique<fl::Engine>(fis.name);
  for (const FuzzyInput& input : fis.inputs) {
    auto variable = std::make_unique<fl::InputVariable>(input.name, input.min, input.max);
    variable->setEnabled(true);
    variable->setLockValueInRange(input.lock_range);
    for (const FuzzySet& set : input.sets) {
      const Membership& m = set.membership;
      fl::Term* term = nullptr;
      switch (m.shape) {
        case Membership::Shape::kTriangle:
          term = new fl::Triangle(set.name, m.a, m.b, m.c);
          break;
        case Membership::Shape::kTrapezoid:
          term = new fl::Trapezoid(set.name, m.a, m.b, m.c, m.d);
          break;
        case Membership::Shape::kRampUp:
          term = new fl::Ramp(set.name, m.a, m.b);
          break;
        case Membership::Shape::kRampDown:
          term = new fl::Ramp(set.name, m.b, m.a);
          break;
        case Membership::Shape::kGaussian:
          term = new fl::Gaussian(set.name, m.a, m.b);
          break;
      }
      variable->addTerm(term);
    }
    engine->addInputVariable(variable.release());
  }

  auto output =
      std::make_unique<fl::OutputVariable>(fis.output_name, fis.output_min, fis.output_max);
  output->setEnabled(true);
  output->setLockValueInRange(fis.lock_output_range);
  output->setLockPreviousValue(false);
  output->setDefaultValue(fis.default_value);
  output->setDefuzzifier(new fl::WeightedAverage(fl::WeightedDefuzzifier::TakagiSugeno));
  for (std::size_t k = 0; k < fis.output_terms.size(); ++k) {
    output->addTerm(new fl::Constant(fis.output_terms[k], fis.output_values[k]));
  }
  engine->addOutputVariable(output.release());

  auto rule_block = std::make_unique<fl::RuleBlock>("rules");
  rule_block->setEnabled(true);
  rule_block->setConjunction(new fl::AlgebraicProduct);
  rule_block->setActivation(new fl::General);
  for (const FuzzyRule& rule : fis.rules) {
    rule_block->addRule(fl::Rule::parse(RuleText(fis, rule), engine.get()));
  }
  engine->addRuleBlock(rule_block.release());
  return engine;
}

}  // namespace rabbit

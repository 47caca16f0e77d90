#include "rabbit/learn/fll.h"

#include <fl/Headers.h>

#include <charconv>
#include <cmath>
#include <cstddef>
#include <fstream>
#include <mutex>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "rabbit/io/atomic_file.h"
#include "rabbit/io/bounded_read.h"
#include "rabbit/io/csv.h"
#include "rabbit/io/error.h"

namespace rabbit {
namespace {

// ---------------------------------------------------------------------------------------------
// Placing errors: a scan of the text the way fuzzylite's FllImporter reads it (text after '#' is
// a comment; every other non-empty line is `key: value`; InputVariable, OutputVariable and
// RuleBlock open blocks), so that the i-th variable of the engine is the i-th block of its kind
// and its j-th term the j-th `term:` line of that block.

bool IsBlank(char ch) { return std::isspace(static_cast<unsigned char>(ch)) != 0; }

std::string Trim(const std::string& text) {
  std::size_t begin = 0;
  std::size_t end = text.size();
  while (begin < end && IsBlank(text[begin])) ++begin;
  while (end > begin && IsBlank(text[end - 1])) --end;
  return text.substr(begin, end - begin);
}

struct FllEntry {
  int line = 0;
  std::string key, value;
};

struct FllBlock {
  std::string tag;  // InputVariable, OutputVariable or RuleBlock
  FllEntry header;  // its opening line (value: the name as written)
  std::vector<FllEntry> entries;
};

bool SplitKeyValue(const std::string& raw_line, int number, FllEntry* entry) {
  const std::string content = Trim(raw_line.substr(0, raw_line.find('#')));
  const std::size_t colon = content.find(':');
  if (content.empty() || colon == std::string::npos) return false;
  entry->line = number;
  entry->key = Trim(content.substr(0, colon));
  entry->value = Trim(content.substr(colon + 1));
  return true;
}

std::vector<FllBlock> ScanBlocks(const std::vector<std::string>& lines) {
  std::vector<FllBlock> blocks;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    FllEntry entry;
    if (!SplitKeyValue(lines[i], static_cast<int>(i + 1), &entry)) continue;
    if (entry.key == "InputVariable" || entry.key == "OutputVariable" || entry.key == "RuleBlock") {
      blocks.push_back(FllBlock{entry.key, entry, {}});
    } else if (!blocks.empty()) {
      blocks.back().entries.push_back(entry);
    }
  }
  return blocks;
}

std::vector<const FllBlock*> BlocksOf(const std::vector<FllBlock>& blocks, const std::string& tag) {
  std::vector<const FllBlock*> result;
  for (const FllBlock& block : blocks) {
    if (block.tag == tag) result.push_back(&block);
  }
  return result;
}

// The `occurrence`-th entry of `key` in the block (0-based), or nullptr.
const FllEntry* EntryOf(const FllBlock& block, const std::string& key, std::size_t occurrence = 0) {
  for (const FllEntry& entry : block.entries) {
    if (entry.key == key && occurrence-- == 0) return &entry;
  }
  return nullptr;
}

// The line of that entry, else the block's header line.
int LineOf(const FllBlock& block, const std::string& key, std::size_t occurrence = 0) {
  const FllEntry* entry = EntryOf(block, key, occurrence);
  return entry ? entry->line : block.header.line;
}

// fuzzylite's exception text without its "{at file:line}" trailer.
std::string CleanMessage(const std::string& what) {
  return Trim(what.substr(0, what.find("\n{at")));
}

// The importer stops at the first line it cannot read; the shortest prefix of the text that fails
// to import ends with that line (blocks are processed at the next block or at the end).
int FailingLine(const std::vector<std::string>& lines) {
  // Whether a prefix of the file imports flips once, from fine to failing: binary search for the
  // shortest failing prefix (O(log n) imports, so a long malformed file cannot stall us).
  auto fails = [&lines](std::size_t n) {
    std::string prefix;
    for (std::size_t i = 0; i < n; ++i) {
      prefix += lines[i];
      prefix += '\n';
    }
    try {
      std::unique_ptr<fl::Engine> partial(fl::FllImporter().fromString(prefix));
    } catch (const std::exception&) {
      return true;
    }
    return false;
  };
  if (lines.empty() || !fails(lines.size())) return 0;
  std::size_t lo = 1, hi = lines.size();  // the answer is in [lo, hi]
  while (lo < hi) {
    const std::size_t mid = lo + (hi - lo) / 2;
    if (fails(mid)) {
      hi = mid;
    } else {
      lo = mid + 1;
    }
  }
  return static_cast<int>(lo);
}

// Silences fuzzylite's logging to stdout (FL_LOG) while alive.
// Holds a process-wide lock while fuzzylite's logging is off: the switch is global, so two imports
// at once (on two threads) would restore each other's setting.
class QuietFuzzylite {
 public:
  QuietFuzzylite() : lock_(Mutex()), was_logging_(fl::fuzzylite::isLogging()) {
    fl::fuzzylite::setLogging(false);
  }
  ~QuietFuzzylite() { fl::fuzzylite::setLogging(was_logging_); }
  QuietFuzzylite(const QuietFuzzylite&) = delete;
  QuietFuzzylite& operator=(const QuietFuzzylite&) = delete;

 private:
  static std::mutex& Mutex() {
    static std::mutex mutex;
    return mutex;
  }
  std::lock_guard<std::mutex> lock_;
  bool was_logging_;
};

std::string Quote(const std::string& name) { return "'" + name + "'"; }

// ---------------------------------------------------------------------------------------------
// Compiling an imported engine into a TsFis.

class Compiler {
 public:
  Compiler(const fl::Engine& engine, const std::vector<FllBlock>& blocks, const std::string& file)
      : engine_(engine), blocks_(blocks), file_(file) {}

  TsFis Compile() {
    const auto inputs = BlocksOf(blocks_, "InputVariable");
    const auto outputs = BlocksOf(blocks_, "OutputVariable");
    const auto rule_blocks = BlocksOf(blocks_, "RuleBlock");
    if (inputs.size() != engine_.numberOfInputVariables() ||
        outputs.size() != engine_.numberOfOutputVariables() ||
        rule_blocks.size() != engine_.numberOfRuleBlocks()) {
      Fail(0, "", "could not match the file's blocks with fuzzylite's engine");
    }
    if (inputs.empty()) Fail(0, "InputVariable", "no input variables");
    if (outputs.size() != 1) {
      Fail(outputs.empty() ? 0 : outputs[1]->header.line, "OutputVariable",
           "exactly one output variable is supported, found " + std::to_string(outputs.size()));
    }
    if (rule_blocks.size() != 1) {
      Fail(rule_blocks.empty() ? 0 : rule_blocks[1]->header.line, "RuleBlock",
           "exactly one rule block is supported, found " + std::to_string(rule_blocks.size()));
    }

    TsFis fis;
    fis.name = engine_.getName();
    for (std::size_t i = 0; i < inputs.size(); ++i) {
      fis.inputs.push_back(CompileInput(*engine_.getInputVariable(i), *inputs[i]));
      for (std::size_t j = 0; j < i; ++j) {
        if (fis.inputs[j].name == fis.inputs[i].name) {
          Fail(inputs[i]->header.line, "InputVariable",
               "two input variables named " + Quote(fis.inputs[i].name));
        }
      }
    }
    CompileOutput(*engine_.getOutputVariable(0), *outputs[0], &fis);
    for (const FuzzyInput& input : fis.inputs) {
      if (input.name == fis.output_name) {
        Fail(outputs[0]->header.line, "OutputVariable",
             "the output variable has the name of an input, " + Quote(input.name));
      }
    }
    CompileRules(*engine_.getRuleBlock(0), *rule_blocks[0], &fis);

    std::string why;
    if (!fis.IsValid(&why)) Fail(0, "", why);
    return fis;
  }

 private:
  [[noreturn]] void Fail(int line, const std::string& key, const std::string& message) const {
    throw InputError(file_, line, key, message);
  }

  // fuzzylite's importer keeps only the identifier characters of a name; refuse the others
  // rather than rename silently.
  void CheckName(const std::string& written, const std::string& imported, int line,
                 const std::string& key, const std::string& what) const {
    if (written != imported) {
      Fail(line, key,
           what + " name " + Quote(written) +
               " is not an FLL identifier (letters, digits, '_' and '.')");
    }
  }

  FuzzyInput CompileInput(const fl::InputVariable& variable, const FllBlock& block) const {
    FuzzyInput input;
    input.name = variable.getName();
    CheckName(block.header.value, input.name, block.header.line, "InputVariable", "input variable");
    const std::string where = "input variable " + Quote(input.name);
    if (!variable.isEnabled()) {
      Fail(LineOf(block, "enabled"), "enabled", where + " is disabled; not supported");
    }
    input.min = variable.getMinimum();
    input.max = variable.getMaximum();
    if (!std::isfinite(input.min) || !std::isfinite(input.max) || !(input.min <= input.max)) {
      Fail(LineOf(block, "range"), "range", where + ": the range needs finite min <= max");
    }
    input.lock_range = variable.isLockValueInRange();
    if (variable.numberOfTerms() == 0)
      Fail(block.header.line, "InputVariable", where + ": no terms");
    for (std::size_t j = 0; j < variable.numberOfTerms(); ++j) {
      const FllEntry* entry = EntryOf(block, "term", j);
      const int line = entry ? entry->line : block.header.line;
      const fl::Term* term = variable.getTerm(j);
      FuzzySet set;
      set.name = term->getName();
      if (entry)
        CheckName(Trim(entry->value.substr(0, entry->value.find(' '))), set.name, line, "term",
                  "term");
      const std::string term_where = where + " term " + Quote(set.name);
      for (const FuzzySet& other : input.sets) {
        if (other.name == set.name) Fail(line, "term", term_where + " is defined twice");
      }
      set.membership = CompileMembership(*term, line, term_where);
      input.sets.push_back(set);
    }
    return input;
  }

  Membership CompileMembership(const fl::Term& term, int line, const std::string& where) const {
    Membership m;
    if (const auto* triangle = dynamic_cast<const fl::Triangle*>(&term)) {
      m.shape = Membership::Shape::kTriangle;
      m.a = triangle->getVertexA();
      m.b = triangle->getVertexB();
      m.c = triangle->getVertexC();
    } else if (const auto* trapezoid = dynamic_cast<const fl::Trapezoid*>(&term)) {
      m.shape = Membership::Shape::kTrapezoid;
      m.a = trapezoid->getVertexA();
      m.b = trapezoid->getVertexB();
      m.c = trapezoid->getVertexC();
      m.d = trapezoid->getVertexD();
    } else if (const auto* ramp = dynamic_cast<const fl::Ramp*>(&term)) {
      // Ramp start end: 0 at start, 1 at end. Rising: RampUp {start, end}; falling: RampDown
      // {end, start}; start == end (0 everywhere) is left to Membership::IsValid to refuse.
      const double start = ramp->getStart();
      const double end = ramp->getEnd();
      if (start > end) {
        m.shape = Membership::Shape::kRampDown;
        m.a = end;
        m.b = start;
      } else {
        m.shape = Membership::Shape::kRampUp;
        m.a = start;
        m.b = end;
      }
    } else if (const auto* gaussian = dynamic_cast<const fl::Gaussian*>(&term)) {
      m.shape = Membership::Shape::kGaussian;
      m.a = gaussian->getMean();
      m.b = gaussian->getStandardDeviation();
    } else {
      Fail(line, "term",
           where + ": term type " + Quote(term.className()) +
               " is not supported (Triangle, Trapezoid, Ramp, Gaussian)");
    }
    if (term.getHeight() != 1.0) {
      std::ostringstream height;
      height << term.getHeight();
      Fail(line, "term", where + ": height " + height.str() + " is not supported (only 1)");
    }
    std::string why;
    if (!m.IsValid(&why)) Fail(line, "term", where + ": " + why);
    return m;
  }

  void CompileOutput(const fl::OutputVariable& variable, const FllBlock& block, TsFis* fis) const {
    fis->output_name = variable.getName();
    CheckName(block.header.value, fis->output_name, block.header.line, "OutputVariable",
              "output variable");
    const std::string where = "output variable " + Quote(fis->output_name);
    if (!variable.isEnabled()) {
      Fail(LineOf(block, "enabled"), "enabled", where + " is disabled; not supported");
    }
    if (variable.isLockPreviousValue()) {
      const bool valid = EntryOf(block, "lock-valid") != nullptr;
      const std::string key = valid ? "lock-valid" : "lock-previous";
      Fail(LineOf(block, key), key,
           where +
               ": lock-previous: true (a stateful output) is not "
               "supported");
    }
    const fl::Defuzzifier* defuzzifier = variable.getDefuzzifier();
    const auto* weighted = dynamic_cast<const fl::WeightedAverage*>(defuzzifier);
    if (!weighted) {
      Fail(LineOf(block, "defuzzifier"), "defuzzifier",
           where + ": the defuzzifier must be WeightedAverage (TakagiSugeno), found " +
               Quote(defuzzifier ? defuzzifier->className() : "none"));
    }
    if (weighted->getType() == fl::WeightedDefuzzifier::Tsukamoto) {
      Fail(LineOf(block, "defuzzifier"), "defuzzifier",
           where + ": WeightedAverage Tsukamoto is not supported (TakagiSugeno or Automatic)");
    }
    fis->output_min = variable.getMinimum();
    fis->output_max = variable.getMaximum();
    if (!std::isfinite(fis->output_min) || !std::isfinite(fis->output_max) ||
        !(fis->output_min <= fis->output_max)) {
      Fail(LineOf(block, "range"), "range", where + ": the range needs finite min <= max");
    }
    fis->lock_output_range = variable.isLockValueInRange();
    fis->default_value = variable.getDefaultValue();
    if (std::isinf(fis->default_value)) {
      Fail(LineOf(block, "default"), "default", where + ": the default value is infinite");
    }
    if (variable.numberOfTerms() == 0) {
      Fail(block.header.line, "OutputVariable", where + ": no terms");
    }
    for (std::size_t j = 0; j < variable.numberOfTerms(); ++j) {
      const FllEntry* entry = EntryOf(block, "term", j);
      const int line = entry ? entry->line : block.header.line;
      const fl::Term* term = variable.getTerm(j);
      const std::string name = term->getName();
      if (entry)
        CheckName(Trim(entry->value.substr(0, entry->value.find(' '))), name, line, "term", "term");
      const std::string term_where = where + " term " + Quote(name);
      const auto* constant = dynamic_cast<const fl::Constant*>(term);
      if (!constant) {
        Fail(line, "term",
             term_where + ": term type " + Quote(term->className()) +
                 " is not supported for the output (only Constant: zero-order "
                 "Takagi-Sugeno)");
      }
      if (!std::isfinite(constant->getValue())) {
        Fail(line, "term", term_where + ": the value must be finite");
      }
      for (const std::string& other : fis->output_terms) {
        if (other == name) Fail(line, "term", term_where + " is defined twice");
      }
      fis->output_terms.push_back(name);
      fis->output_values.push_back(constant->getValue());
    }
  }

  void CompileRules(const fl::RuleBlock& rule_block, const FllBlock& block, TsFis* fis) const {
    if (!rule_block.isEnabled()) {
      Fail(LineOf(block, "enabled"), "enabled", "the rule block is disabled; not supported");
    }
    const fl::TNorm* conjunction = rule_block.getConjunction();
    if (!conjunction || conjunction->className() != "AlgebraicProduct") {
      Fail(LineOf(block, "conjunction"), "conjunction",
           "the conjunction must be AlgebraicProduct (eq. 9), found " +
               Quote(conjunction ? conjunction->className() : "none"));
    }
    const fl::Activation* activation = rule_block.getActivation();
    if (activation && activation->className() != "General") {
      Fail(LineOf(block, "activation"), "activation",
           "the activation must be General, found " + Quote(activation->className()));
    }
    if (rule_block.numberOfRules() == 0) Fail(block.header.line, "RuleBlock", "no rules");
    for (std::size_t r = 0; r < rule_block.numberOfRules(); ++r) {
      fis->rules.push_back(CompileRule(*rule_block.getRule(r), LineOf(block, "rule", r), *fis));
    }
  }

  FuzzyRule CompileRule(const fl::Rule& rule, int line, const TsFis& fis) const {
    const std::string where = "rule " + Quote(rule.getText());
    if (!rule.isLoaded()) {
      std::string why =
          "could not be loaded when read (does it name a variable defined after the rule block?)";
      try {
        fl::Rule copy;
        copy.load(rule.getText(), &engine_);
      } catch (const std::exception& e) {
        why = CleanMessage(e.what());
      }
      Fail(line, "rule", where + ": " + why);
    }
    if (!rule.isEnabled()) Fail(line, "rule", where + " is disabled; not supported");
    if (rule.getWeight() != 1.0) {
      Fail(line, "rule", where + ": rule weights ('with') are not supported");
    }
    FuzzyRule compiled;
    compiled.antecedent.assign(fis.inputs.size(), -1);
    AddAntecedent(rule.getAntecedent()->getExpression(), line, where, &compiled);
    for (std::size_t i = 0; i < fis.inputs.size(); ++i) {
      if (compiled.antecedent[i] < 0) {
        Fail(line, "rule",
             where + " does not name input " + Quote(fis.inputs[i].name) +
                 " (every rule must name every input once)");
      }
    }
    const std::vector<fl::Proposition*>& conclusions = rule.getConsequent()->conclusions();
    if (conclusions.size() != 1) {
      Fail(line, "rule", where + ": exactly one conclusion is supported");
    }
    const fl::Proposition& conclusion = *conclusions[0];
    if (conclusion.variable != engine_.getOutputVariable(0)) {
      Fail(line, "rule", where + ": the conclusion must be about the output variable");
    }
    if (!conclusion.hedges.empty()) {
      Fail(line, "rule",
           where + ": hedges (" + Quote(conclusion.hedges[0]->name()) + ") are not supported");
    }
    compiled.consequent = IndexOf(engine_.getOutputVariable(0)->terms(), conclusion.term);
    if (compiled.consequent < 0) Fail(line, "rule", where + ": unknown output term");
    return compiled;
  }

  template <typename T>
  static int IndexOf(const std::vector<T*>& items, const void* item) {
    for (std::size_t i = 0; i < items.size(); ++i) {
      if (items[i] == item) return static_cast<int>(i);
    }
    return -1;
  }

  void AddAntecedent(const fl::Expression* expression, int line, const std::string& where,
                     FuzzyRule* rule) const {
    if (!expression) Fail(line, "rule", where + ": empty antecedent");
    if (expression->type() == fl::Expression::Operator) {
      const auto* op = static_cast<const fl::Operator*>(expression);
      if (op->name != fl::Rule::andKeyword()) {
        Fail(line, "rule",
             where + ": only 'and' is supported in antecedents, found " + Quote(op->name));
      }
      AddAntecedent(op->left, line, where, rule);
      AddAntecedent(op->right, line, where, rule);
      return;
    }
    const auto* proposition = static_cast<const fl::Proposition*>(expression);
    if (!proposition->hedges.empty()) {
      Fail(line, "rule",
           where + ": hedges (" + Quote(proposition->hedges[0]->name()) + ") are not supported");
    }
    const int input = IndexOf(engine_.inputVariables(), proposition->variable);
    if (input < 0) {
      Fail(line, "rule",
           where + ": " + Quote(proposition->variable ? proposition->variable->getName() : "") +
               " in the antecedent is not an input variable");
    }
    const fl::InputVariable* variable = engine_.getInputVariable(static_cast<std::size_t>(input));
    const int set = IndexOf(variable->terms(), proposition->term);
    if (set < 0) Fail(line, "rule", where + ": unknown term of " + Quote(variable->getName()));
    int& slot = rule->antecedent[static_cast<std::size_t>(input)];
    if (slot >= 0) {
      Fail(line, "rule", where + " names input " + Quote(variable->getName()) + " twice");
    }
    slot = set;
  }

  const fl::Engine& engine_;
  const std::vector<FllBlock>& blocks_;
  const std::string& file_;
};

}  // namespace

TsFis ParseFll(const std::string& text, const std::string& file) {
  const QuietFuzzylite quiet;
  const std::vector<std::string> lines = SplitLines(text);
  std::unique_ptr<fl::Engine> engine;
  try {
    engine.reset(fl::FllImporter().fromString(text));
  } catch (const std::exception& e) {
    const int line = FailingLine(lines);
    FllEntry entry;
    if (line > 0) SplitKeyValue(lines[static_cast<std::size_t>(line - 1)], line, &entry);
    throw InputError(file, line, entry.key, "malformed FLL: " + CleanMessage(e.what()));
  }
  const std::vector<FllBlock> blocks = ScanBlocks(lines);
  return Compiler(*engine, blocks, file).Compile();
}

TsFis LoadFll(const std::string& path) {
  return ParseFll(ReadBoundedFile(path, kFllFileLimits), path);
}

}  // namespace rabbit

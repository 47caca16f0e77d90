#include "rabbit/learn/multi_cmac.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

namespace rabbit {
namespace {

constexpr double kMaxQuanta = 16777216.0;  // 2^24 per dimension, as the SISO CMAC

// Number of detectors of `layer` along a dimension of `quanta` quanta and detector `width`.
int DetectorsAlong(int quanta, int layer, int width) { return (quanta - 1 + layer) / width + 1; }

}  // namespace

bool MultiCmacOptions::IsValid(std::string* error) const {
  auto fail = [error](const std::string& message) {
    if (error != nullptr) *error = message;
    return false;
  };
  if (layers < 1 || layers > kMaxCmacLayers) {
    return fail("layers must be in [1, " + std::to_string(kMaxCmacLayers) + "], got " +
                std::to_string(layers));
  }
  if (inputs.empty() || inputs.size() > static_cast<size_t>(kMaxMultiCmacInputs)) {
    return fail("needs 1 to " + std::to_string(kMaxMultiCmacInputs) + " inputs, got " +
                std::to_string(inputs.size()));
  }
  for (size_t i = 0; i < inputs.size(); ++i) {
    const MultiCmacInput& in = inputs[i];
    const std::string which = "input " + std::to_string(i) + ": ";
    if (!std::isfinite(in.quantum) || !(in.quantum > 0.0)) {
      return fail(which + "quantum must be finite and > 0");
    }
    if (in.width < 1) return fail(which + "width must be >= 1 quantum");
    if (layers > in.width) return fail(which + "layers must be <= width (offsets repeat)");
    if (!std::isfinite(in.x_min) || !std::isfinite(in.x_max) || !(in.x_min < in.x_max)) {
      return fail(which + "the range needs finite x_min < x_max");
    }
    if (!((in.x_max - in.x_min) / in.quantum <= kMaxQuanta)) {
      return fail(which + "too many quanta over the range ((x_max - x_min) / quantum <= 2^24)");
    }
  }
  if (hash_table_size < 1) return fail("hash_table_size must be >= 1");
  return true;
}

MultiCmac::MultiCmac(const MultiCmacOptions& options) : options_(options) {
  std::string error;
  if (!options_.IsValid(&error)) throw std::invalid_argument("MultiCmac: " + error);
  num_inputs_ = static_cast<int>(options_.inputs.size());
  for (int i = 0; i < num_inputs_; ++i) {
    const MultiCmacInput& in = options_.inputs[i];
    quanta_[i] = CmacNumQuanta(in.x_max - in.x_min, in.quantum);
  }
  weights_.assign(static_cast<size_t>(options_.hash_table_size), 0.0);
}

bool MultiCmac::Quantize(const double* x, int* k) const {
  for (int i = 0; i < num_inputs_; ++i) {
    const MultiCmacInput& in = options_.inputs[i];
    k[i] = CmacQuantize(x[i], in.x_min, in.x_max, in.quantum, quanta_[i]);
    if (k[i] < 0) return false;
  }
  return true;
}

void MultiCmac::LayerDetectors(int layer, const int* k, int* detector) const {
  for (int i = 0; i < num_inputs_; ++i) detector[i] = (k[i] + layer) / options_.inputs[i].width;
}

int MultiCmac::Slot(int layer, const int* detector) const {
  std::uint64_t h = CmacHashStep(options_.hash_seed, static_cast<std::uint64_t>(layer));
  for (int i = 0; i < num_inputs_; ++i)
    h = CmacHashStep(h, static_cast<std::uint64_t>(detector[i]));
  return static_cast<int>(h % static_cast<std::uint64_t>(options_.hash_table_size));
}

void MultiCmac::Active(const double* x, CmacActive* active) const {
  std::array<int, kMaxMultiCmacInputs> k;
  if (!Quantize(x, k.data())) {
    active->count = 0;
    return;
  }
  std::array<int, kMaxMultiCmacInputs> detector;
  active->count = options_.layers;
  for (int j = 0; j < options_.layers; ++j) {
    LayerDetectors(j, k.data(), detector.data());
    active->index[j] = Slot(j, detector.data());
  }
}

double MultiCmac::Query(const double* x) const {
  std::array<int, kMaxMultiCmacInputs> k;
  if (!Quantize(x, k.data())) return std::numeric_limits<double>::quiet_NaN();
  std::array<int, kMaxMultiCmacInputs> detector;
  double sum = 0.0;
  for (int j = 0; j < options_.layers; ++j) {
    LayerDetectors(j, k.data(), detector.data());
    sum += weights_[Slot(j, detector.data())];
  }
  return sum;
}

double MultiCmac::Update(const double* x, double target, double beta) {
  CmacActive active;
  Active(x, &active);
  if (active.count == 0) return std::numeric_limits<double>::quiet_NaN();
  double output = 0.0;
  for (int j = 0; j < active.count; ++j) output += weights_[active.index[j]];
  if (!std::isfinite(target) || !std::isfinite(beta)) return output;
  const double step = beta * (target - output) / options_.layers;
  for (int j = 0; j < active.count; ++j) weights_[active.index[j]] += step;
  return output;
}

double MultiCmac::NumVirtualDetectors() const {
  double total = 0.0;
  for (int j = 0; j < options_.layers; ++j) {
    double product = 1.0;
    for (int i = 0; i < num_inputs_; ++i) {
      product *= DetectorsAlong(quanta_[i], j, options_.inputs[i].width);
    }
    total += product;
  }
  return total;
}

namespace {

// Counts the entries of `slots` (one per distinct detector) whose slot another entry shares.
int CountShared(std::vector<int>* slots) {
  std::sort(slots->begin(), slots->end());
  int shared = 0;
  for (size_t i = 0; i < slots->size(); ++i) {
    const bool same_as_previous = i > 0 && (*slots)[i - 1] == (*slots)[i];
    const bool same_as_next = i + 1 < slots->size() && (*slots)[i + 1] == (*slots)[i];
    if (same_as_previous || same_as_next) ++shared;
  }
  return shared;
}

}  // namespace

int MultiCmac::NumCollisions(const double* points, int count) const {
  // Key: (layer, d_0, ..., d_{n-1}); unused tail entries stay 0.
  using Key = std::array<int, kMaxMultiCmacInputs + 1>;
  std::vector<Key> keys;
  keys.reserve(static_cast<size_t>(std::max(count, 0)) * static_cast<size_t>(options_.layers));
  std::array<int, kMaxMultiCmacInputs> k;
  for (int p = 0; p < count; ++p) {
    if (!Quantize(points + static_cast<std::ptrdiff_t>(p) * num_inputs_, k.data())) continue;
    for (int j = 0; j < options_.layers; ++j) {
      Key key{};
      key[0] = j;
      LayerDetectors(j, k.data(), key.data() + 1);
      keys.push_back(key);
    }
  }
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  std::vector<int> slots;
  slots.reserve(keys.size());
  for (const Key& key : keys) slots.push_back(Slot(key[0], key.data() + 1));
  return CountShared(&slots);
}

int MultiCmac::NumCollisionsOverRange() const {
  if (NumVirtualDetectors() > kMaxEnumeratedDetectors) return -1;
  std::vector<int> slots;
  slots.reserve(static_cast<size_t>(NumVirtualDetectors()));
  std::array<int, kMaxMultiCmacInputs> count{};
  std::array<int, kMaxMultiCmacInputs> detector{};
  for (int j = 0; j < options_.layers; ++j) {
    for (int i = 0; i < num_inputs_; ++i) {
      count[i] = DetectorsAlong(quanta_[i], j, options_.inputs[i].width);
      detector[i] = 0;
    }
    // Odometer over the layer's detector tuples.
    while (true) {
      slots.push_back(Slot(j, detector.data()));
      int i = 0;
      while (i < num_inputs_ && ++detector[i] == count[i]) detector[i++] = 0;
      if (i == num_inputs_) break;
    }
  }
  return CountShared(&slots);
}

}  // namespace rabbit

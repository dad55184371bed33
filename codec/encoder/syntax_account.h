// SPDX-License-Identifier: BSD-2-Clause
// The encoder's account of where a frame's bits go: the range encoder adds each coded
// bin's cost (-log2 of its probability as coded; 1 for a bypass bin) to the syntax
// element the writers have declared current with a SyntaxScope. An estimate, not a
// measurement of bytes: the sum of all elements stays within a fraction of a percent of
// the payload (the range coder's flush and rounding make the difference). Nothing of it
// is coded.
// Threading: an account belongs to one encoder (single-threaded).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

namespace svc::codec {

// What a coded bin is for (docs/encoder.md, "Syntax accounting").
enum class SyntaxElement : uint8_t {
  // Frame header fields, and any bin no other element claims.
  kHeader,
  // Skip flags, the macroblock type and prediction direction (intra, forward, backward,
  // bidirectional, warp), luma and chroma intra modes including CfL parameters.
  kModes,
  // Inter partitions, transform size splits and transform types.
  kPartitions,
  // Motion vector differences, vector predictor indices, warp nodes, epipolar lines.
  kVectors,
  // The coefficient syntax: coded-block flags, end of block, significance, levels,
  // signs and their Golomb / bypass remainders.
  kLevels,
  // CDEF and loop filter syntax.
  kFilters,
};

inline constexpr size_t kSyntaxElements = 6;

// "header", "modes", "partitions", "vectors", "levels", "filters".
constexpr const char* syntax_element_name(SyntaxElement element) {
  constexpr const char* kNames[kSyntaxElements] = {"header", "modes", "partitions", "vectors", "levels", "filters"};
  return static_cast<size_t>(element) < kSyntaxElements ? kNames[static_cast<size_t>(element)] : "unknown";
}

struct SyntaxBits {
  std::array<double, kSyntaxElements> bits{};  // by SyntaxElement
  SyntaxElement current = SyntaxElement::kHeader;

  void add(SyntaxElement element, double count) { bits[static_cast<size_t>(element)] += count; }
  double total() const {
    double sum = 0;
    for (double b : bits) sum += b;
    return sum;
  }
  double of(SyntaxElement element) const { return bits[static_cast<size_t>(element)]; }
  SyntaxBits& operator+=(const SyntaxBits& other) {
    for (size_t e = 0; e < kSyntaxElements; ++e) bits[e] += other.bits[e];
    return *this;
  }
};

// Declares, for its lifetime, what the bins an encoder codes are for; restores the
// previous element when it ends, so scopes nest. Does nothing for an encoder without an
// account. `Encoder` is RangeEncoder (a template so that this header needs no other).
template <class Encoder>
class SyntaxScope {
 public:
  SyntaxScope(Encoder& encoder, SyntaxElement element) : account_(encoder.account()) {
    if (account_ == nullptr) return;
    previous_ = account_->current;
    account_->current = element;
  }
  ~SyntaxScope() {
    if (account_ != nullptr) account_->current = previous_;
  }
  SyntaxScope(const SyntaxScope&) = delete;
  SyntaxScope& operator=(const SyntaxScope&) = delete;

 private:
  SyntaxBits* account_;
  SyntaxElement previous_ = SyntaxElement::kHeader;
};

template <class Encoder>
SyntaxScope(Encoder&, SyntaxElement) -> SyntaxScope<Encoder>;

}  // namespace svc::codec

// SPDX-License-Identifier: BSD-2-Clause
// Exact integer division rounded toward minus infinity, the rounding the geometry of
// vector predictors and cube padding specifies (docs/codec.md). It sits on the decoder's
// path for every macroblock's vector predictors, where a 64-bit integer division, among
// the slowest instructions of x86 cores, costs several times a double one.
// Threading: pure functions.
#pragma once

#include <cstdint>

namespace svc::codec {

// floor(a / b) for b > 0, by the integer instructions alone: the definition that
// floor_divide is checked against.
constexpr int64_t floor_divide_reference(int64_t a, int64_t b) {
  const int64_t q = a / b;
  return (a % b != 0 && a < 0) ? q - 1 : q;
}

// floor(a / b) for b > 0, equal to floor_divide_reference for every such a and b.
// Operands below 2^52 in magnitude are exact doubles, and their quotient, rounded by
// any rounding mode, lies in [F, F + 1] for the true floor F (rounding is monotonic
// and keeps integers); truncated it is F or F + 1, and the remainder tells which.
inline int64_t floor_divide(int64_t a, int64_t b) {
  constexpr int64_t kExact = int64_t{1} << 52;
  if (a <= -kExact || a >= kExact || b >= kExact) return floor_divide_reference(a, b);
  const auto q = static_cast<int64_t>(static_cast<double>(a) / static_cast<double>(b));
  return a - q * b < 0 ? q - 1 : q;
}

}  // namespace svc::codec

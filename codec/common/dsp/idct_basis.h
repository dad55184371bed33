// SPDX-License-Identifier: BSD-2-Clause
// The integer inverse DCT's constants: part of the bitstream contract (docs/codec.md),
// shared by the kernel and the matrix-product definition in codec/dct.cc, and the scalar
// column pass its variants fall back to.
#pragma once

#include <cstdint>

namespace svc::codec::dsp {

// round(basis(u, x) * 16384), x < 4 (the other half follows from
// basis(u, 7 - x) = (-1)^u basis(u, x)). Spelled out because the decoder's output depends
// on every digit. Each column sums to 43284 in absolute value: with coefficients in
// [-2048, 2047] the row pass fits in 32 bits (|sum| < 2^27) and its output in 18 bits;
// the column pass accumulates in 64 bits.
inline constexpr int kIdctBasis[8][4] = {
    {5793, 5793, 5793, 5793},     // u = 0
    {8035, 6811, 4551, 1598},     // u = 1
    {7568, 3135, -3135, -7568},   // u = 2
    {6811, -1598, -8035, -4551},  // u = 3
    {5793, -5793, -5793, 5793},   // u = 4
    {4551, -8035, 1598, 6811},    // u = 5
    {3135, -7568, 7568, -3135},   // u = 6
    {1598, -4551, 6811, -8035},   // u = 7
};
inline constexpr int kIdctRowShift = 9;      // row pass keeps 5 extra fractional bits
inline constexpr int kIdctColumnShift = 19;  // 14 + 14 - 9

// The column pass in 64 bits over row-pass outputs stored by column (columns[x][v]),
// exactly as the plain kernel computes it: the variants' fallback when a row-pass output
// leaves 16 bits.
inline void idct_column_pass_scalar(const int32_t columns[8][8], int16_t* samples) {
  for (int x = 0; x < 8; ++x) {
    for (int y = 0; y < 8; ++y) {
      int64_t sum = int64_t{1} << (kIdctColumnShift - 1);
      for (int v = 0; v < 8; ++v) {
        const int b = y < 4 ? kIdctBasis[v][y] : ((v & 1) ? -kIdctBasis[v][7 - y] : kIdctBasis[v][7 - y]);
        sum += int64_t{b} * columns[x][v];
      }
      samples[8 * y + x] = static_cast<int16_t>(sum >> kIdctColumnShift);
    }
  }
}

}  // namespace svc::codec::dsp

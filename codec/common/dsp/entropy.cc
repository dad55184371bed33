// SPDX-License-Identifier: BSD-2-Clause
// Plain symbol search of the range decoder (docs/codec.md 2.3): the symbol is the
// number of interval bounds at or below the code value. The bounds increase with k, so
// counting them all, without an early exit, gives the same answer as a search.
#include "codec/common/dsp/dsp_init.h"

namespace svc::codec::dsp {
namespace {

int find_symbol_c(const uint16_t* cumulative, int count, uint32_t scale, uint32_t code) {
  int symbol = 0;
  for (int k = 1; k < count; ++k) symbol += scale * cumulative[k - 1] + static_cast<uint32_t>(k) <= code;
  return symbol;
}

}  // namespace

void init_entropy_c(DspTable* table) { table->find_symbol = find_symbol_c; }

}  // namespace svc::codec::dsp

// SPDX-License-Identifier: BSD-2-Clause
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>

#include "codec/common/dsp/dsp.h"
#include "codec/encoder/dsp/encoder_dsp.h"

namespace svc::codec::dsp {
namespace {

constexpr int k8x8 = size_index(TransformSize::k8x8);

template <class Table>
bool same_table(const Table& a, const Table& b) {
  return std::memcmp(&a, &b, sizeof(Table)) == 0;
}

// Every pointer of a table of kernels is set.
template <class Table>
void expect_every_entry_set(const Table& table, unsigned flags) {
  const auto* entries = reinterpret_cast<const unsigned char*>(&table);
  for (size_t offset = 0; offset < sizeof(Table); offset += sizeof(void*)) {
    void* entry;
    std::memcpy(&entry, entries + offset, sizeof entry);
    EXPECT_NE(entry, nullptr) << "flags " << flags << ", entry " << offset / sizeof(void*);
  }
}

// The process's table is the one for the detected features, restricted by SVC_CPU_MASK
// when set (the suite runs these tests once with SVC_CPU_MASK=0).
TEST(DspTable, FollowsDetectedFeaturesAndCpuMask) {
  unsigned expected = detected_cpu_flags();
  if (const char* mask = std::getenv("SVC_CPU_MASK"); mask != nullptr && *mask != '\0') {
    expected &= static_cast<unsigned>(std::strtoul(mask, nullptr, 0));
  }
  EXPECT_EQ(active_cpu_flags(), expected);
  EXPECT_TRUE(same_table(get_dsp(), make_dsp_table(expected)));
  EXPECT_TRUE(same_table(get_encoder_dsp(), make_encoder_dsp_table(expected)));
}

TEST(DspTable, EveryEntryIsSetForEveryFeatureSet) {
  for (unsigned flags :
       {0u, unsigned{kCpuSse2}, unsigned{kCpuSse2 | kCpuSse41}, unsigned{kCpuNeon}, detected_cpu_flags()}) {
    expect_every_entry_set(make_dsp_table(flags), flags);
    expect_every_entry_set(make_encoder_dsp_table(flags), flags);
  }
}

TEST(DspTable, PlainTableDiffersFromOptimizedWhereVariantsExist) {
  if ((detected_cpu_flags() & kCpuSse2) == 0) GTEST_SKIP() << "no SSE2 on this machine";
  const DspTable plain = make_dsp_table(0), sse2 = make_dsp_table(kCpuSse2);
  EXPECT_NE(plain.put_intermediate, sse2.put_intermediate);
  EXPECT_NE(plain.inverse_transform[k8x8][0], sse2.inverse_transform[k8x8][0]);
  const EncoderDspTable plain_encoder = make_encoder_dsp_table(0), sse2_encoder = make_encoder_dsp_table(kCpuSse2);
  EXPECT_NE(plain_encoder.forward_dct_8x8, sse2_encoder.forward_dct_8x8);
  EXPECT_EQ(plain_encoder.quantize_8x8, sse2_encoder.quantize_8x8);  // no SSE2 variant: the reference stays
}

TEST(DspTable, NeonTableDiffersFromPlainWhereVariantsExist) {
  if ((detected_cpu_flags() & kCpuNeon) == 0) GTEST_SKIP() << "no NEON on this machine";
  const DspTable plain = make_dsp_table(0), neon = make_dsp_table(kCpuNeon);
  EXPECT_NE(plain.interpolate_8tap, neon.interpolate_8tap);
  EXPECT_NE(plain.inverse_transform[k8x8][0], neon.inverse_transform[k8x8][0]);
  const EncoderDspTable plain_encoder = make_encoder_dsp_table(0), neon_encoder = make_encoder_dsp_table(kCpuNeon);
  EXPECT_NE(plain_encoder.sad_16x16, neon_encoder.sad_16x16);
  EXPECT_EQ(plain_encoder.forward_dct_8x8, neon_encoder.forward_dct_8x8);  // float: no variant
}

}  // namespace
}  // namespace svc::codec::dsp

// SPDX-License-Identifier: BSD-2-Clause
#include "codec/common/context_priors.h"

#include <atomic>
#include <vector>

namespace svc::codec {

// The generated tables (context_priors_table.cc).
extern const std::span<const uint16_t> kIntraFramePriors;
extern const std::span<const uint16_t> kBFramePriors;

namespace {

std::atomic<ContextObserver> observer{nullptr};

template <class Planes, class F>
void for_each_intra_frame_context(Planes& luma, Planes& chroma, F&& f) {
  for_each_context(luma, f);
  for_each_context(chroma, f);
}

// Primes the contexts `visit` walks with `priors`, in order (a table shorter than the
// bundle, which the tests rule out, leaves the rest at 1/2). While training, contexts
// start at 1/2, so that the tables do not learn from themselves.
template <class Visit>
void prime(std::span<const uint16_t> priors, Visit&& visit) {
  if (observer.load() != nullptr) return;
  size_t i = 0;
  visit([&](AdaptiveBit& bit) {
    if (i < priors.size()) bit.prime(priors[i++]);
  });
}

template <class Visit>
void observe(ContextBundle bundle, Visit&& visit) {
  const ContextObserver report = observer.load();
  if (report == nullptr) return;
  std::vector<uint16_t> probabilities;
  std::vector<uint8_t> seen;
  visit([&](const AdaptiveBit& bit) {
    probabilities.push_back(static_cast<uint16_t>(bit.probability_of_zero()));
    seen.push_back(bit.seen);
  });
  report(bundle, probabilities, seen);
}

}  // namespace

int context_count(ContextBundle bundle) {
  int count = 0;
  const auto tally = [&](const AdaptiveBit&) { ++count; };
  if (bundle == ContextBundle::kIntraFrame) {
    const intra::PlaneContexts plane;
    for_each_intra_frame_context(plane, plane, tally);
  } else {
    const bframe::SyntaxContexts contexts;
    for_each_context(contexts, tally);
  }
  return count;
}

std::span<const uint16_t> context_priors(ContextBundle bundle) {
  return bundle == ContextBundle::kIntraFrame ? kIntraFramePriors : kBFramePriors;
}

void prime_intra_frame_contexts(intra::PlaneContexts& luma, intra::PlaneContexts& chroma) {
  prime(kIntraFramePriors, [&](auto&& f) { for_each_intra_frame_context(luma, chroma, f); });
}

void prime_bframe_contexts(bframe::SyntaxContexts& contexts) {
  prime(kBFramePriors, [&](auto&& f) { for_each_context(contexts, f); });
}

void set_context_observer(ContextObserver report) { observer.store(report); }

void observe_intra_frame_contexts(const intra::PlaneContexts& luma, const intra::PlaneContexts& chroma) {
  observe(ContextBundle::kIntraFrame, [&](auto&& f) { for_each_intra_frame_context(luma, chroma, f); });
}

void observe_bframe_contexts(const bframe::SyntaxContexts& contexts) {
  observe(ContextBundle::kBFrame, [&](auto&& f) { for_each_context(contexts, f); });
}

}  // namespace svc::codec

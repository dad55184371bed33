// SPDX-License-Identifier: BSD-2-Clause
// Enables an instruction set for the functions that follow, up to SVC_TARGET_END, with
// each compiler's own pragma: GCC's target pragma, clang's attribute push (clang ignores
// GCC's). A kernel file includes its intrinsics headers first, then opens the region.
#pragma once

#define SVC_TARGET_STRINGIFY(text) #text
#if defined(__clang__)
#define SVC_TARGET_BEGIN(features) \
  _Pragma(SVC_TARGET_STRINGIFY(clang attribute push(__attribute__((target(features))), apply_to = function)))
#define SVC_TARGET_END _Pragma("clang attribute pop")
#else
#define SVC_TARGET_BEGIN(features) _Pragma("GCC push_options") _Pragma(SVC_TARGET_STRINGIFY(GCC target(features)))
#define SVC_TARGET_END _Pragma("GCC pop_options")
#endif

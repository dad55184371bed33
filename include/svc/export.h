// SPDX-License-Identifier: BSD-2-Clause
/* Marks the public API's symbols (C and C++): the libraries are built with every other
   symbol hidden, so an embedder links against the documented interface alone. Define
   SVC_SHARED when linking a Windows DLL build of the library. */
#ifndef SVC_EXPORT_H
#define SVC_EXPORT_H

#if defined(_WIN32) || defined(__CYGWIN__)
#if defined(SVC_BUILDING_LIBRARY) && defined(SVC_SHARED)
#define SVC_API __declspec(dllexport)
#elif defined(SVC_SHARED)
#define SVC_API __declspec(dllimport)
#else
#define SVC_API
#endif
#elif defined(__GNUC__) || defined(__clang__)
#define SVC_API __attribute__((visibility("default")))
#else
#define SVC_API
#endif

#endif /* SVC_EXPORT_H */

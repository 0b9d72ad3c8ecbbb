/* softlight/version.h - the library's version, and the mark of the functions it exports.
 *
 * SL_VERSION_MAJOR changes when the public API or ABI breaks, MINOR when it grows, PATCH for
 * fixes. The shared library's SONAME carries the major number. SL_API marks each public
 * function: the library is built with hidden visibility, so only what carries SL_API is
 * exported from libsoftlight.so; everything else stays private to the library. */
#ifndef SOFTLIGHT_VERSION_H
#define SOFTLIGHT_VERSION_H

#define SL_VERSION_MAJOR 0
#define SL_VERSION_MINOR 9
#define SL_VERSION_PATCH 0
#define SL_VERSION_STRING "0.9.0"

#if defined(__GNUC__) || defined(__clang__)
#define SL_API __attribute__((visibility("default")))
#else
#define SL_API
#endif

#endif

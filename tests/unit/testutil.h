/* testutil.h - shared helpers for the cmocka tests: paths, temporary files, float checks.
 * Tests run from the source root (CTest's WORKING_DIRECTORY), so "scenes/..." paths work. */
#ifndef SL_TESTUTIL_H
#define SL_TESTUTIL_H

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

/* A fresh temporary directory for this test process (removed by the OS's tmp cleaning). */
const char *test_tmpdir(void);
/* test_tmpdir()/name, in a static buffer rotated over 8 slots. */
const char *test_tmpfile(const char *name);
/* Write bytes to a file (asserts on failure). */
void test_write_bytes(const char *path, const void *bytes, size_t size);
/* Assert |a - b| <= tol, printing both values and the difference on failure. */
#define assert_near(a, b, tol) test_assert_near((double)(a), (double)(b), (double)(tol), #a, #b, __FILE__, __LINE__)
void test_assert_near(double a, double b, double tol, const char *sa, const char *sb, const char *file, int line);

/* Environments for the IBL tests: an sl_env whose w x h texels hold fn at their centre
 * directions (the specification's lat-long map, row 0 = v 0 = +Z), mip chain built. */
#include "ibl/ibl.h"
typedef double (*test_env_fn)(const double w[3], int channel);
void test_texel_centre_dir(int w, int h, int i, int j, double d[3]);
sl_env test_make_env(int w, int h, test_env_fn fn);

#endif

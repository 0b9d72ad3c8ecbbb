/* testutil.c - see testutil.h. */
#include "testutil.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <math.h>
#include <unistd.h>

const char *test_tmpdir(void)
{
    static char dir[256];
    if (!dir[0]) {
        const char *base = getenv("TMPDIR");
        snprintf(dir, sizeof dir, "%s/softlight-test-XXXXXX", base && base[0] ? base : "/tmp");
        if (!mkdtemp(dir)) {
            fprintf(stderr, "cannot create a temporary directory\n");
            fail();
        }
    }
    return dir;
}

const char *test_tmpfile(const char *name)
{
    static char slots[8][512];
    static int next;
    char *p = slots[next++ & 7];
    snprintf(p, 512, "%s/%s", test_tmpdir(), name);
    return p;
}

void test_write_bytes(const char *path, const void *bytes, size_t size)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(bytes, 1, size, f), size);
    assert_int_equal(fclose(f), 0);
}

void test_assert_near(double a, double b, double tol, const char *sa, const char *sb, const char *file, int line)
{
    double d = a - b;
    if (!(d <= tol && -d <= tol)) {
        print_error("%s:%d: %s = %.9g and %s = %.9g differ by %.3g (tolerance %.3g)\n", file, line, sa, a, sb,
                    b, d, tol);
        _fail(file, line);
    }
}

void test_texel_centre_dir(int w, int h, int i, int j, double d[3])
{
    const double pi = 3.14159265358979323846;
    double phi = 2.0 * pi * (0.5 - (i + 0.5) / w), theta = pi * (j + 0.5) / h;
    d[0] = cos(phi) * sin(theta);
    d[1] = sin(phi) * sin(theta);
    d[2] = cos(theta);
}

sl_env test_make_env(int w, int h, test_env_fn fn)
{
    sl_image img;
    sl_error err = {0};
    assert_true(sl_image_alloc(&img, w, h, 3, &err));
    for (int j = 0; j < h; j++)
        for (int i = 0; i < w; i++) {
            double d[3];
            test_texel_centre_dir(w, h, i, j, d);
            float *p = sl_image_pixel(&img, i, j);
            for (int c = 0; c < 3; c++)
                p[c] = (float)fn(d, c);
        }
    sl_env env;
    assert_true(sl_env_build(&env, &img, &err));
    sl_image_free(&img);
    return env;
}

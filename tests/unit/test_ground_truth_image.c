/* test_ground_truth_image.c - ground truth of a whole G-buffer (src/shading/ground_truth_image.c):
 * every covered pixel equals the per-pixel reference sl_ground_truth_shade for the N and V the
 * lighting shader forms (both G terms), rows come out top first, the cache round-trips bit for
 * bit and is recomputed whenever an input changes or the file is damaged, the progress
 * callback reports every pixel, and the result does not depend on the thread count.
 *
 * A 32x16 analytic environment keeps each pixel at 512 texels, so the whole file runs in
 * milliseconds (also under ASan). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "shading/ground_truth_image.h"
#include "testutil.h"

#define PI 3.14159265358979323846

enum { GW = 6, GH = 4 };

/* A smooth sky with a bright lobe, different per channel, so the three channels and the
 * rotation all matter. */
static sl_env make_env(void)
{
    const int w = 32, h = 16;
    sl_image img;
    sl_error err = {0};
    assert_true(sl_image_alloc(&img, w, h, 3, &err));
    for (int j = 0; j < h; j++)
        for (int i = 0; i < w; i++) {
            vec3 d = sl_uv_to_dir(vec2(((float)i + 0.5f) / (float)w, ((float)j + 0.5f) / (float)h));
            float lobe = powf(maxf(0.0f, d.x * 0.6f + d.y * 0.3f + d.z * 0.74f), 8.0f);
            float *p = sl_image_pixel(&img, i, j);
            p[0] = 0.2f + 5.0f * lobe;
            p[1] = 0.3f + 0.5f * d.z * d.z + 2.0f * lobe;
            p[2] = 0.4f + 0.3f * (d.x > 0.0f ? d.x : 0.0f);
        }
    sl_env env;
    assert_true(sl_env_build(&env, &img, 0, &err));
    sl_image_free(&img);
    return env;
}

/* A 6x4 G-buffer: a few covered texels with assorted normals and materials, the rest empty. */
static void make_gbuffer(sl_gbuffer *gb)
{
    sl_error err = {0};
    memset(gb, 0, sizeof *gb);
    assert_true(sl_gbuffer_resize(gb, GW, GH, &err));
    sl_gbuffer_clear(gb, 0);
    struct {
        int x, y;
        vec3 p, n;
        float kd, ks, alpha;
    } px[] = {
        {0, 0, {0, 0, 0}, {0, 0, 1}, 0.5f, 0.04f, 1.0f},
        {3, 0, {1, 0, 0}, {0.6f, 0.0f, 0.8f}, 0.2f, 0.9f, 100.0f},
        {5, 1, {0, 1, 0}, {0, -1, 0}, 0.7f, 0.2f, 10.0f},
        {2, 2, {-1, 0, 0.5f}, {-1, 0, 0}, 0.1f, 0.5f, 1000.0f},
        {4, 3, {0.5f, 0.5f, 0}, {0.0f, -0.6f, 0.8f}, 0.3f, 0.04f, 0.0f},
    };
    for (size_t i = 0; i < sizeof px / sizeof px[0]; i++) {
        sl_gbuffer_texel *t = sl_gbuffer_at(gb, px[i].x, px[i].y);
        t->position = px[i].p;
        t->normal = px[i].n;
        t->kd = vec3(px[i].kd, 0.5f * px[i].kd, 0.25f);
        t->ks = vec3(px[i].ks, px[i].ks, 0.5f * px[i].ks);
        t->alpha = px[i].alpha;
        t->depth = 0.5f;
    }
}

typedef struct {
    sl_env env;
    sl_gbuffer gb;
    sl_gt_image_desc desc;
} fixture;

static int setup(void **state)
{
    fixture *f = calloc(1, sizeof *f);
    f->env = make_env();
    make_gbuffer(&f->gb);
    f->desc = (sl_gt_image_desc){.env = &f->env, .gbuffer = &f->gb, .eye = vec3(0.0f, -5.0f, 3.0f),
                                 .env_rotation_deg = 30.0f, .env_intensity = 1.5f, .threads = 2};
    *state = f;
    return 0;
}

static int teardown(void **state)
{
    fixture *f = *state;
    sl_env_free(&f->env);
    sl_gbuffer_free(&f->gb);
    free(f);
    return 0;
}

static void assert_rel(double got, double want, double rel, const char *what, int x, int y, int ch)
{
    double tol = rel * fabs(want) + 1e-30;
    if (!(fabs(got - want) <= tol))
        fail_msg("%s at %d,%d channel %d: got %.9g, want %.9g (off by %.3g, tolerance %.3g)", what, x, y, ch, got,
                 want, got - want, tol);
}

/* Every pixel against sl_ground_truth_shade, with N and V formed by hand as the shader forms them. */
static void test_matches_per_pixel_reference(void **state)
{
    fixture *f = *state;
    sl_error err = {0};
    sl_gt_image img;
    assert_true(sl_gt_image_compute(&img, &f->desc, &err));
    assert_int_equal(img.covered, 5);
    assert_false(img.from_cache);
    sl_ground_truth gt;
    assert_true(sl_ground_truth_init(&gt, &f->env, &err));
    int nonzero = 0;
    for (int y = 0; y < GH; y++)
        for (int x = 0; x < GW; x++) {
            const sl_gbuffer_texel *t = sl_gbuffer_at(&f->gb, x, y);
            int row = GH - 1 - y; /* image row 0 = top */
            float m = sl_image_pixel(&img.mask, x, row)[0];
            if (!sl_gbuffer_covered(t)) {
                assert_true(m == 0.0f);
                for (int ch = 0; ch < 3; ch++) {
                    assert_true(sl_image_pixel(&img.diffuse, x, row)[ch] == 0.0f);
                    assert_true(sl_image_pixel(&img.specular[0], x, row)[ch] == 0.0f);
                    assert_true(sl_image_pixel(&img.specular[1], x, row)[ch] == 0.0f);
                }
                continue;
            }
            assert_true(m == 1.0f);
            vec3 V = normalize(sub(f->desc.eye, t->position));
            double nv = (double)dot(t->normal, V);
            if (nv < 0.01)
                continue; /* bent normals: test_bent_normal */
            for (int g = 0; g < 2; g++) {
                sl_gt_query q = {.n = t->normal, .v = V, .kd = t->kd, .ks = t->ks, .alpha = (double)t->alpha,
                                 .g = (sl_gt_geometry)g, .rotation = 30.0 * PI / 180.0, .intensity = 1.5};
                sl_gt_result r;
                assert_true(sl_ground_truth_shade(&gt, &q, &r, &err));
                for (int ch = 0; ch < 3; ch++) {
                    assert_rel(sl_image_pixel(&img.diffuse, x, row)[ch], r.diffuse[ch], 1e-6, "diffuse", x, y, ch);
                    assert_rel(sl_image_pixel(&img.specular[g], x, row)[ch], r.specular[ch], 1e-6,
                               g ? "specular G=1" : "specular G=1/(L.H)^2", x, y, ch);
                    nonzero += r.specular[ch] > 0.0;
                }
            }
        }
    assert_true(nonzero > 12); /* the comparison compared something */
    /* total = diffuse + specular */
    sl_image total = {0};
    assert_true(sl_gt_image_total(&img, SL_GT_G_ONE, &total, &err));
    for (int i = 0; i < GW * GH * 3; i++)
        assert_true(total.data[i] == img.diffuse.data[i] + img.specular[1].data[i]);
    sl_image_free(&total);
    sl_ground_truth_free(&gt);
    sl_gt_image_free(&img);
}

/* A normal facing away from the eye is bent to N.V = 0.01 first, as lighting.frag does. */
static void test_bent_normal(void **state)
{
    fixture *f = *state;
    sl_error err = {0};
    sl_gt_image img;
    assert_true(sl_gt_image_compute(&img, &f->desc, &err));
    const sl_gbuffer_texel *t = sl_gbuffer_at(&f->gb, 2, 2); /* normal -X, eye towards +X of it: N.V < 0 */
    double V[3] = {0.0 - -1.0, -5.0 - 0.0, 3.0 - 0.5}, len = sqrt(V[0] * V[0] + V[1] * V[1] + V[2] * V[2]);
    for (int i = 0; i < 3; i++)
        V[i] /= len;
    double nv = -V[0]; /* N = (-1, 0, 0) */
    assert_true(nv < 0.0);
    double N[3] = {-1.0 + (0.01 - nv) * V[0], (0.01 - nv) * V[1], (0.01 - nv) * V[2]};
    double nl = sqrt(N[0] * N[0] + N[1] * N[1] + N[2] * N[2]);
    sl_ground_truth gt;
    assert_true(sl_ground_truth_init(&gt, &f->env, &err));
    sl_gt_query q = {.n = vec3((float)(N[0] / nl), (float)(N[1] / nl), (float)(N[2] / nl)),
                     .v = vec3((float)V[0], (float)V[1], (float)V[2]), .kd = t->kd, .ks = t->ks,
                     .alpha = (double)t->alpha, .g = SL_GT_G_INV_LH2, .rotation = 30.0 * PI / 180.0, .intensity = 1.5};
    sl_gt_result r;
    assert_true(sl_ground_truth_shade(&gt, &q, &r, &err));
    /* float N and V: alpha 1000 magnifies a 1e-7 direction change to ~1e-4 relative */
    for (int ch = 0; ch < 3; ch++) {
        assert_rel(sl_image_pixel(&img.diffuse, 2, GH - 1 - 2)[ch], r.diffuse[ch], 1e-4, "bent diffuse", 2, 2, ch);
        assert_rel(sl_image_pixel(&img.specular[0], 2, GH - 1 - 2)[ch], r.specular[ch], 1e-3, "bent specular", 2, 2,
                   ch);
    }
    assert_true(r.diffuse[0] > 0.0 && r.specular[0] > 0.0);
    sl_ground_truth_free(&gt);
    sl_gt_image_free(&img);
}

static void assert_same_gt_images(const sl_gt_image *a, const sl_gt_image *b)
{
    assert_int_equal(a->width, b->width);
    assert_int_equal(a->height, b->height);
    assert_int_equal(a->covered, b->covered);
    assert_same_image(&a->diffuse, &b->diffuse, "ground truth, diffuse");
    assert_same_image(&a->specular[0], &b->specular[0], "ground truth, specular (G 1/(L.H)^2)");
    assert_same_image(&a->specular[1], &b->specular[1], "ground truth, specular (G = 1)");
    assert_same_image(&a->mask, &b->mask, "ground truth, mask");
}

static void test_cache_round_trip_and_invalidation(void **state)
{
    fixture *f = *state;
    sl_error err = {0};
    const char *path = test_tmpfile("truth.gt");
    remove(path);
    sl_gt_image_desc d = f->desc;
    d.cache_path = path;
    d.label = "test scene";
    sl_gt_image a, b;
    assert_true(sl_gt_image_compute(&a, &d, &err));
    assert_false(a.from_cache);
    assert_true(sl_gt_image_compute(&b, &d, &err));
    assert_true(b.from_cache);
    assert_true(b.seconds == 0.0);
    assert_true(a.key == b.key && a.key == sl_gt_image_key(&d));
    assert_same_gt_images(&a, &b);
    sl_gt_image_free(&b);

    /* The header says what made it. */
    FILE *fp = fopen(path, "rb");
    assert_non_null(fp);
    char head[256] = {0};
    assert_true(fread(head, 1, sizeof head - 1, fp) > 0);
    fclose(fp);
    assert_non_null(strstr(head, "softlight ground truth v1\nlabel test scene\nsize 6 4\ncovered 5\n"));

    /* Any input change is a miss (and rewrites the cache). */
    sl_gt_image c;
    sl_gbuffer_at(&f->gb, 3, 0)->kd.x = 0.21f;
    assert_true(sl_gt_image_compute(&c, &d, &err));
    assert_false(c.from_cache);
    assert_true(c.key != a.key);
    assert_true(sl_image_pixel(&c.diffuse, 3, GH - 1)[0] != sl_image_pixel(&a.diffuse, 3, GH - 1)[0]);
    sl_gt_image_free(&c);
    sl_gbuffer_at(&f->gb, 3, 0)->kd.x = 0.2f;
    assert_true(sl_gt_image_compute(&c, &d, &err)); /* back to the original inputs: recomputed, same bits */
    assert_false(c.from_cache);
    assert_same_gt_images(&a, &c);
    sl_gt_image_free(&c);
    sl_gt_image_desc d2 = d;
    d2.env_intensity = 2.0f;
    assert_true(sl_gt_image_compute(&c, &d2, &err));
    assert_false(c.from_cache);
    assert_rel(sl_image_pixel(&c.diffuse, 0, GH - 1)[0], sl_image_pixel(&a.diffuse, 0, GH - 1)[0] * 2.0 / 1.5, 1e-6,
               "diffuse x intensity", 0, 0, 0);
    sl_gt_image_free(&c);
    d2 = d;
    d2.eye.z += 0.5f;
    assert_true(sl_gt_image_key(&d2) != sl_gt_image_key(&d));
    d2 = d;
    d2.env_rotation_deg = 31.0f;
    assert_true(sl_gt_image_key(&d2) != sl_gt_image_key(&d));
    f->env.levels[0].texels[7].y += 0.5f;
    assert_true(sl_gt_image_key(&d) != a.key);
    f->env.levels[0].texels[7].y -= 0.5f;
    assert_true(sl_gt_image_key(&d) == a.key);

    /* A damaged file (truncated, or a NaN in the data) is recomputed, not an error. */
    assert_true(sl_gt_image_compute(&c, &d, &err)); /* rewrite the good cache */
    sl_gt_image_free(&c);
    unsigned char *bytes;
    size_t size;
    assert_true(sl_read_file(path, 1 << 20, &bytes, &size, &err));
    test_write_bytes(path, bytes, size - 4);
    assert_true(sl_gt_image_compute(&c, &d, &err));
    assert_false(c.from_cache);
    assert_same_gt_images(&a, &c);
    sl_gt_image_free(&c);
    const unsigned char nan_le[4] = {0x00, 0x00, 0xc0, 0x7f};
    memcpy(bytes + size - 8, nan_le, 4);
    test_write_bytes(path, bytes, size);
    assert_true(sl_gt_image_compute(&c, &d, &err));
    assert_false(c.from_cache);
    assert_same_gt_images(&a, &c);
    sl_gt_image_free(&c);
    free(bytes);
    sl_gt_image_free(&a);
}

typedef struct {
    int calls;
    long last_done, last_total;
    bool monotonic;
} progress_log;

static void on_progress(void *user, long done, long total)
{
    progress_log *log = user;
    if (done < log->last_done)
        log->monotonic = false;
    log->calls++;
    log->last_done = done;
    log->last_total = total;
}

static void test_progress_and_threads(void **state)
{
    fixture *f = *state;
    sl_error err = {0};
    progress_log log = {.monotonic = true};
    sl_gt_image_desc d = f->desc;
    d.threads = 1;
    d.progress = on_progress;
    d.progress_user = &log;
    sl_gt_image one, two;
    assert_true(sl_gt_image_compute(&one, &d, &err));
    /* one thread: a call after every row with a covered pixel left to do, then the final one */
    assert_true(log.calls >= 2);
    assert_true(log.monotonic);
    assert_int_equal(log.last_done, 5);
    assert_int_equal(log.last_total, 5);
    d.threads = 2;
    d.progress = NULL;
    assert_true(sl_gt_image_compute(&two, &d, &err));
    assert_same_gt_images(&one, &two);
    sl_gt_image_free(&one);
    sl_gt_image_free(&two);
}

static void test_bad_input(void **state)
{
    fixture *f = *state;
    sl_error err = {0};
    sl_gt_image img;
    sl_gt_image_desc d = f->desc;
    d.env = NULL;
    assert_false(sl_gt_image_compute(&img, &d, &err));
    assert_int_equal(err.code, SL_ERR_RANGE);
    d = f->desc;
    d.env_intensity = -1.0f;
    assert_false(sl_gt_image_compute(&img, &d, &err));
    d = f->desc;
    sl_gbuffer_at(&f->gb, 5, 1)->normal.y = NAN;
    assert_false(sl_gt_image_compute(&img, &d, &err));
    assert_non_null(strstr(err.msg, "5,1"));
    sl_gbuffer_at(&f->gb, 5, 1)->normal.y = -1.0f;
    d.cache_path = "/nonexistent-dir/truth.gt";
    assert_false(sl_gt_image_compute(&img, &d, &err));
    assert_int_equal(err.code, SL_ERR_IO);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_matches_per_pixel_reference, setup, teardown),
        cmocka_unit_test_setup_teardown(test_bent_normal, setup, teardown),
        cmocka_unit_test_setup_teardown(test_cache_round_trip_and_invalidation, setup, teardown),
        cmocka_unit_test_setup_teardown(test_progress_and_threads, setup, teardown),
        cmocka_unit_test_setup_teardown(test_bad_input, setup, teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

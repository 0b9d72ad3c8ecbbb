/* test_exr_envmaps.c - the shipped environments as OpenEXR: each
 * scenes/envmaps/NAME.hdr converted through softlight's own writer (sl_exr_encode) to float and half
 * files with several compressions, read back by the environment reader and rendered.
 *
 * Expected, per environment:
 * - float (32-bit), any lossless compression, scanline or tiled: every texel back bit for bit, and
 *   scenes/default.json rendered under it gives the same radiance, bit for bit, as under the .hdr
 *   (the pipeline sees the same floats);
 * - half: every texel is the nearest half of the .hdr's float (ties to even; computed here with
 *   frexp/nearbyint, independently of OpenEXR's conversion). For a .hdr that is the texel itself:
 *   an RGBE texel is an 8-bit mantissa times a power of two, which half's 11-bit significand holds
 *   exactly while the value stays inside half's range (2^-24 .. 65504; the shipped maps run from
 *   5.96e-8 = 2^-24 to 3.4e4, printed with the test). So the test counts the texels half
 *   changes; where none changes (every shipped map, measured) the render must be bit for bit the
 *   .hdr's, otherwise within 2^-11 relative (each term of the lighting is a positive weighted sum
 *   of texels: mips, irradiance, samples) with 1e-5 of slack for float rounding along the way.
 * The measured figures print with the test (docs/ibl.md "OpenEXR environments"). */
#include "testutil.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/exr.h"
#include "core/image.h"
#include "render/renderer.h"
#include "scene/scene.h"

static const char *const envmaps[] = {"city", "forest", "interior", "studio", "sunset"};

typedef struct {
    const char *name;
    sl_exr_options o;
    bool render; /* also render under it (one float and one half per environment keep it fast) */
} variant;

static const variant variants[] = {
    {"float-zip", {.half = false, .compression = SL_EXR_ZIP}, true},
    {"float-piz", {.half = false, .compression = SL_EXR_PIZ}, false},
    {"float-rle-tiled64", {.half = false, .compression = SL_EXR_RLE, .tile = 64}, false},
    {"half-zip", {.half = true, .compression = SL_EXR_ZIP}, true},
    {"half-piz", {.half = true, .compression = SL_EXR_PIZ}, false},
    {"half-pxr24", {.half = true, .compression = SL_EXR_PXR24}, false}, /* lossless for half */
};

#define HALF_REL (1.0 / 2048.0) /* 2^-11: half's rounding, relative */

/* The nearest half to v >= 0 (ties to even), as a float; INFINITY above half's range. */
static float nearest_half(float v)
{
    if (v == 0.0f)
        return 0.0f;
    int k;
    frexpf(v, &k);           /* v = m 2^k, m in [0.5, 1): v's binade starts at 2^(k-1) */
    int e = k - 1 < -14 ? -14 : k - 1; /* below 2^-14 the subnormals' fixed step 2^-24 */
    float r = ldexpf(nearbyintf(ldexpf(v, 10 - e)), e - 10);
    return r > 65504.0f ? INFINITY : r;
}

/* Radiance of scenes/default.json at 96x54, N = 8, under the environment file `env`. */
static void render_under(const char *env, sl_image *out)
{
    sl_error err = {0};
    sl_scene scene;
    if (!sl_scene_load("scenes/default.json", &scene, &err))
        fail_msg("%s", err.msg);
    snprintf(scene.environment.hdr_path, sizeof scene.environment.hdr_path, "%s", env);
    sl_render_desc desc = {0};
    sl_option_set_size(&desc.options, 96, 54);
    sl_option_set_threads(&desc.options, 1);
    sl_option_set_samples(&desc.options, 8);
    sl_renderer r;
    if (!sl_renderer_init(&r, &scene, &desc, &err) || !sl_renderer_frame(&r, NULL, &err))
        fail_msg("%s: %s", env, err.msg);
    assert_true(sl_image_alloc(out, r.radiance.width, r.radiance.height, r.radiance.channels, NULL));
    memcpy(out->data, r.radiance.data, sizeof(float) * (size_t)out->width * (size_t)out->height * (size_t)out->channels);
    sl_renderer_free(&r);
    sl_scene_free(&scene);
}

static size_t floats_of(const sl_image *img)
{
    return (size_t)img->width * (size_t)img->height * (size_t)img->channels;
}

static void test_shipped_environments_as_exr(void **state)
{
    (void)state;
    for (size_t m = 0; m < sizeof envmaps / sizeof envmaps[0]; m++) {
        char hdr[256];
        snprintf(hdr, sizeof hdr, "scenes/envmaps/%s.hdr", envmaps[m]);
        sl_error err = {0};
        sl_image src;
        sl_image_repairs rep;
        if (!sl_image_read_radiance(hdr, 0, &src, &rep, &err))
            fail_msg("%s", err.msg);
        float peak = 0.0f, low = INFINITY;
        for (size_t i = 0; i < floats_of(&src); i++) {
            peak = fmaxf(peak, src.data[i]);
            low = src.data[i] > 0.0f ? fminf(low, src.data[i]) : low;
        }
        print_message("%s: %dx%d, texels from %.3g to %.3g\n", hdr, src.width, src.height, (double)low, (double)peak);
        sl_image ref;
        render_under(hdr, &ref);
        for (size_t v = 0; v < sizeof variants / sizeof variants[0]; v++) {
            const variant *var = &variants[v];
            unsigned char *bytes;
            size_t size;
            sl_exr_layer layer = {"", "RGB", &src};
            if (!sl_exr_encode(&layer, 1, &var->o, &bytes, &size, &err))
                fail_msg("%s %s: %s", envmaps[m], var->name, err.msg);
            char name[64];
            snprintf(name, sizeof name, "%s-%s.exr", envmaps[m], var->name);
            const char *path = test_tmpfile(name);
            test_write_bytes(path, bytes, size);
            free(bytes);
            sl_image back;
            if (!sl_image_read_radiance(path, 0, &back, &rep, &err))
                fail_msg("%s: %s", name, err.msg);
            assert_int_equal(back.width, src.width);
            assert_int_equal(back.height, src.height);
            assert_int_equal(back.channels, 3);
            double tex_rel = 0.0;
            size_t changed = 0;
            for (size_t i = 0; i < floats_of(&src); i++) {
                float want = var->o.half ? nearest_half(src.data[i]) : src.data[i];
                if (memcmp(&want, &back.data[i], sizeof want) != 0)
                    fail_msg("%s: float %zu is %.9g, want %.9g (the .hdr's %.9g)", name, i, (double)back.data[i],
                             (double)want, (double)src.data[i]);
                changed += back.data[i] != src.data[i];
                if (src.data[i] >= 6.103515625e-05f) /* half's smallest normal, 2^-14 */
                    tex_rel = fmax(tex_rel, fabs((double)back.data[i] - (double)src.data[i]) / (double)src.data[i]);
            }
            assert_true(tex_rel <= HALF_REL);
            if (!var->render) {
                print_message("%-9s %-18s %8zu bytes, texels %s, %zu changed (max rel %.3g)\n", envmaps[m],
                              var->name, size, var->o.half ? "nearest half" : "bit for bit", changed, tex_rel);
                sl_image_free(&back);
                continue;
            }
            sl_image img;
            render_under(path, &img);
            assert_int_equal(floats_of(&img), floats_of(&ref));
            double img_rel = 0.0;
            for (size_t i = 0; i < floats_of(&img); i++)
                img_rel = fmax(img_rel, fabs((double)img.data[i] - (double)ref.data[i]) / fmax((double)ref.data[i], 1e-6));
            if (changed == 0)
                assert_same_texels(img.data, ref.data, floats_of(&img) / 3, 12, img.width, "%s render", name);
            else
                assert_true(img_rel <= HALF_REL + 1e-5);
            print_message("%-9s %-18s %8zu bytes, texels %s, %zu changed (max rel %.3g), render max rel %.3g%s\n",
                          envmaps[m], var->name, size, var->o.half ? "nearest half" : "bit for bit", changed, tex_rel,
                          img_rel, changed == 0 ? " (bit for bit)" : "");
            sl_image_free(&img);
            sl_image_free(&back);
        }
        sl_image_free(&ref);
        sl_image_free(&src);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_shipped_environments_as_exr),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

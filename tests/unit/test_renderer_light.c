/* test_renderer_light.c - sl_renderer_light (softlight/renderer.h): lighting a G-buffer the caller
 * holds gives, bit for bit, the radiance and display image of sl_renderer_frame when that
 * G-buffer is the frame's own (copied out), also from another camera than the scene's; a
 * G-buffer of another size is refused and leaves the images alone; the display image, tone mapped
 * band by band inside the lighting pass, is the tone map of the radiance on 1 and 2 threads. Only
 * the public API is used, but for the tone map the display is checked against. */
#include "testutil.h"

#include <stdlib.h>
#include <string.h>

#include <softlight/softlight.h>

#include "post/tonemap.h"

static void copy_gbuffer(const sl_gbuffer *from, sl_gbuffer *to)
{
    assert_true(sl_gbuffer_resize(to, from->width, from->height, NULL));
    memcpy(to->texels, from->texels, (size_t)from->width * (size_t)from->height * sizeof *to->texels);
}

static void test_light_matches_frame(void **state)
{
    (void)state;
    sl_error err = {0};
    sl_scene *scene = sl_scene_open("scenes/default.json", &err);
    assert_non_null(scene);
    sl_renderer *r = sl_renderer_create(scene, &(sl_renderer_options){.width = 64, .height = 36, .samples = 8}, &err);
    assert_non_null(r);
    sl_camera cams[2] = {sl_scene_camera(scene), sl_scene_camera(scene)};
    cams[1].eye = (sl_vec3){6.0f, -18.0f, 3.0f};
    for (int c = 0; c < 2; c++) {
        assert_true(sl_renderer_frame(r, &cams[c], &err));
        sl_image radiance = {0}, display = {0};
        assert_true(sl_image_alloc(&radiance, 64, 36, 3, NULL) && sl_image_alloc(&display, 64, 36, 3, NULL));
        memcpy(radiance.data, sl_renderer_radiance(r)->data, 64 * 36 * 3 * sizeof(float));
        memcpy(display.data, sl_renderer_display(r)->data, 64 * 36 * 3 * sizeof(float));
        sl_gbuffer gb = {0};
        copy_gbuffer(sl_renderer_gbuffer(r), &gb);
        /* another frame in between, so that the images hold something else */
        assert_true(sl_renderer_frame(r, &cams[1 - c], &err));
        assert_true(sl_renderer_light(r, &gb, &cams[c], &err));
        assert_same_image(sl_renderer_radiance(r), &radiance, "radiance, camera %d", c);
        assert_same_image(sl_renderer_display(r), &display, "display, camera %d", c);
        sl_gbuffer_free(&gb);
        sl_image_free(&radiance);
        sl_image_free(&display);
    }
    /* a G-buffer of another size */
    sl_gbuffer small = {0};
    assert_true(sl_gbuffer_resize(&small, 32, 18, NULL));
    sl_gbuffer_clear(&small, 0);
    assert_false(sl_renderer_light(r, &small, NULL, &err));
    assert_int_equal(err.code, SL_ERR_RANGE);
    assert_msg_contains(err, "32x18");
    sl_gbuffer_free(&small);
    sl_renderer_destroy(r);
    sl_scene_close(scene);
}

static void test_display_is_tonemapped_radiance(void **state)
{
    (void)state;
    sl_error err = {0};
    sl_scene *scene = sl_scene_open("scenes/default.json", &err);
    assert_non_null(scene);
    sl_image first = {0};
    for (int threads = 1; threads <= 2; threads++) {
        /* 37 rows: the last band is short */
        sl_renderer_options opt = {.width = 61, .height = 37, .samples = 8, .exposure = 1.7f, .threads = threads};
        sl_renderer *r = sl_renderer_create(scene, &opt, &err);
        assert_non_null(r);
        assert_true(sl_renderer_frame(r, NULL, &err));
        sl_image want = {0};
        sl_tonemap_options tm = {.exposure = 1.7f};
        assert_true(sl_tonemap_image(sl_renderer_radiance(r), &want, &tm, 1, &err));
        assert_same_image(sl_renderer_display(r), &want, "display on %d threads", threads);
        if (threads == 1) {
            assert_true(sl_image_alloc(&first, 61, 37, 3, &err));
            memcpy(first.data, want.data, 61 * 37 * 3 * sizeof(float));
        } else {
            assert_same_image(&want, &first, "display on 2 threads against 1");
        }
        sl_image_free(&want);
        sl_renderer_destroy(r);
    }
    sl_image_free(&first);
    sl_scene_close(scene);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_light_matches_frame),
        cmocka_unit_test(test_display_is_tonemapped_radiance),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

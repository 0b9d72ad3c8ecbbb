/* corner_gbuffer.h - G-buffers traced analytically for the occlusion tests (test_gtao.c,
 * test_reflection.c), so that the rasterizer is out of their picture: every pixel centre's ray
 * through the camera against the floor z = 0 and, optionally, the wall x = 0 at z >= 0 facing +x
 * (the wall fills x < 0), both infinite; one material everywhere. */
#ifndef SL_CORNER_GBUFFER_H
#define SL_CORNER_GBUFFER_H

#include <math.h>
#include <stdbool.h>

#include "testutil.h"

#include "raster/gbuffer.h"
#include "scene/camera.h"

/* The camera over the corner where the floor meets the wall, looking down at the floor beside it. */
static inline sl_camera corner_camera(void)
{
    sl_camera c = {0};
    c.eye = vec3(4.0f, -3.0f, 3.0f);
    c.target = vec3(1.0f, 0.0f, 0.0f);
    c.up = vec3(0.0f, 0.0f, 1.0f);
    c.fovy_deg = 50.0f;
    c.znear = 0.05f;
    c.zfar = 100.0f;
    return c;
}

/* The material of every traced texel: the lobe parameter (texel.alpha: >= 0 a Phong exponent,
 * <= -1 GGX) and a grey F0. */
typedef struct {
    float alpha, ks;
} corner_material;

/* The world ray through the centre of pixel (x, y) of a w x h image (row 0 = bottom): origin on
 * the near plane, unit direction. */
static inline void corner_pixel_ray(mat4 inv_view_proj, int x, int y, int w, int h, vec3 *o, vec3 *d)
{
    vec2 ndc = vec2(2.0f * ((float)x + 0.5f) / (float)w - 1.0f, 2.0f * ((float)y + 0.5f) / (float)h - 1.0f);
    vec4 nearp = mat4_mul_vec4(inv_view_proj, vec4(ndc.x, ndc.y, -1.0f, 1.0f));
    vec4 farp = mat4_mul_vec4(inv_view_proj, vec4(ndc.x, ndc.y, 1.0f, 1.0f));
    *o = scale(vec3(nearp.x, nearp.y, nearp.z), 1.0f / nearp.w);
    *d = normalize(sub(scale(vec3(farp.x, farp.y, farp.z), 1.0f / farp.w), *o));
}

/* The nearest hit of the ray o + t d on the floor and (with `wall`) the wall: its t (INFINITY
 * when none) and normal. */
static inline float corner_hit(vec3 o, vec3 d, bool wall, vec3 *n)
{
    float best = INFINITY;
    if (d.z < 0.0f) {
        float t = -o.z / d.z;
        if (!wall || o.x + d.x * t >= 0.0f) {
            best = t;
            *n = vec3(0, 0, 1);
        }
    }
    if (wall && d.x < 0.0f) {
        float t = -o.x / d.x;
        if (o.z + d.z * t >= 0.0f && t < best) {
            best = t;
            *n = vec3(1, 0, 0);
        }
    }
    return best;
}

/* Trace every pixel centre of a w x h G-buffer (resized, cleared, with the extra plane) through
 * the camera; a covered texel gets its hit's position and normal, the material and depth 0.5. */
static inline void corner_trace(sl_gbuffer *gb, const sl_camera *cam, bool wall, int w, int h, corner_material m)
{
    sl_error err = {0};
    assert_true(sl_gbuffer_resize(gb, w, h, &err));
    assert_true(sl_gbuffer_use_extra(gb, true, 1, &err));
    sl_gbuffer_clear(gb, 1);
    mat4 inv = inverse(sl_camera_view_proj(cam, w, h));
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            vec3 o, d, n = vec3(0, 0, 0);
            corner_pixel_ray(inv, x, y, w, h, &o, &d);
            float best = corner_hit(o, d, wall, &n);
            if (!isfinite(best))
                continue;
            sl_gbuffer_texel *t = sl_gbuffer_at(gb, x, y);
            t->position = add(o, scale(d, best));
            t->normal = n;
            t->ks = vec3(m.ks, m.ks, m.ks);
            t->alpha = m.alpha;
            t->depth = 0.5f;
        }
}

#endif

/* synthetic.c - analytic sphere G-buffers (synthetic.h). The ray of a pixel runs from the
 * near to the far plane through its centre, exactly as the lighting shader's background()
 * reconstructs it, so empty pixels and covered ones agree on the camera. */
#include "../core/threads.h"
#include "synthetic.h"

#include <math.h>

#include "../scene/camera.h"

bool sl_gbuffer_synthetic_spheres(sl_gbuffer *gb, int width, int height, const sl_camera *camera,
                                  const sl_synthetic_sphere *spheres, int count, mat4 *inv_view_proj,
                                  int threads,
                                  sl_error *err)
{
    if (count < 0 || (count > 0 && !spheres))
        return sl_fail(err, SL_ERR_RANGE, "synthetic G-buffer: %d spheres", count);
    if (!sl_gbuffer_resize(gb, width, height, err))
        return false;
    sl_gbuffer_clear(gb, threads);
    mat4 vp = sl_camera_view_proj(camera, width, height);
    mat4 inv = inverse(vp);
    if (inv_view_proj)
        *inv_view_proj = inv;
#pragma omp parallel for schedule(static) num_threads(sl_threads(threads))
    for (int y = 0; y < height; y++) {
        for (int x = 0; x < width; x++) {
            float nx = 2.0f * ((float)x + 0.5f) / (float)width - 1.0f;
            float ny = 2.0f * ((float)y + 0.5f) / (float)height - 1.0f;
            vec4 n4 = mat4_mul_vec4(inv, vec4(nx, ny, -1.0f, 1.0f));
            vec4 f4 = mat4_mul_vec4(inv, vec4(nx, ny, 1.0f, 1.0f));
            vec3 o = scale(xyz(n4), 1.0f / n4.w);
            vec3 d = normalize(sub(scale(xyz(f4), 1.0f / f4.w), o));
            float best = INFINITY;
            int hit = -1;
            for (int s = 0; s < count; s++) {
                /* |o + t d - c|^2 = r^2 with |d| = 1: t = -b -+ sqrt(b^2 - c) */
                vec3 oc = sub(o, spheres[s].center);
                float b = dot(oc, d);
                float c = dot(oc, oc) - spheres[s].radius * spheres[s].radius;
                float disc = b * b - c;
                if (disc < 0.0f)
                    continue;
                float t = -b - sqrtf(disc);
                if (t < 0.0f)
                    t = -b + sqrtf(disc);
                if (t >= 0.0f && t < best) {
                    best = t;
                    hit = s;
                }
            }
            if (hit < 0)
                continue;
            vec3 p = add(o, scale(d, best));
            vec4 clip = mat4_mul_vec4(vp, vec4_from3(p, 1.0f));
            float depth = 0.5f * (clip.z / clip.w) + 0.5f;
            if (!(depth >= 0.0f && depth < 1.0f))
                continue;
            sl_gbuffer_texel *t = sl_gbuffer_at(gb, x, y);
            t->position = p;
            t->normal = normalize(sub(p, spheres[hit].center));
            t->kd = spheres[hit].kd;
            t->ks = spheres[hit].ks;
            t->alpha = spheres[hit].alpha;
            t->depth = depth;
        }
    }
    return true;
}

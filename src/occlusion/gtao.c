/* gtao.c - ground-truth-based ambient occlusion over the G-buffer (the method and its limits:
 * gtao.h). Rows are independent, so threads take rows; each pixel reads at most
 * 2 * SL_GTAO_SLICES * SL_GTAO_STEPS texels around it, all within SL_GTAO_MAX_SCREEN of the image
 * height, which keeps the reads in cache as the rows advance. */
#include "gtao.h"

#include <math.h>
#include <stdlib.h>

#include <softlight/lighting.h>

#include "core/threads.h"
#include "scene/camera.h"

/* The 4x4 ordered-dither matrix: each pixel of a 4x4 block turns its slices and shifts its steps
 * by a different 16th, and the blur over the block (blur_row) averages the 16 back into one
 * estimate with 16 x SL_GTAO_SLICES directions: banding traded for noise the blur removes. */
static const unsigned char bayer4[16] = {0, 8, 2, 10, 12, 4, 14, 6, 3, 11, 1, 9, 15, 7, 13, 5};
#define GTAO_PATTERN 16

/* What every pixel shares: the camera's frame and the radius in pixels at unit depth. */
typedef struct {
    vec3 eye, forward, right, up;
    mat4 view_proj;
    float half_width, half_height; /* NDC to pixels */
    float pixels_per_unit; /* screen radius (pixels) of one world unit at view depth 1 */
    float radius, radius2;
    float max_pixels;
    /* the slices' screen directions for each of the 16 turns */
    float dir_x[GTAO_PATTERN][SL_GTAO_SLICES], dir_y[GTAO_PATTERN][SL_GTAO_SLICES];
} gtao_frame;

static gtao_frame frame_of(const sl_gbuffer *gb, const sl_camera *cam, float radius)
{
    gtao_frame f;
    f.eye = cam->eye;
    f.forward = normalize(sub(cam->target, cam->eye));
    f.right = normalize(cross(f.forward, cam->up));
    f.up = cross(f.right, f.forward);
    f.view_proj = sl_camera_view_proj(cam, gb->width, gb->height);
    f.half_width = 0.5f * (float)gb->width;
    f.half_height = 0.5f * (float)gb->height;
    f.pixels_per_unit = 0.5f * (float)gb->height / tanf(0.5f * cam->fovy_deg * (SL_PI / 180.0f));
    f.radius = radius;
    f.radius2 = radius * radius;
    f.max_pixels = SL_GTAO_MAX_SCREEN * (float)gb->height;
    /* half a turn covers every slice: each runs both ways */
    for (int k = 0; k < GTAO_PATTERN; k++)
        for (int i = 0; i < SL_GTAO_SLICES; i++) {
            float phi = SL_PI * ((float)i + ((float)k + 0.5f) / GTAO_PATTERN) / (float)SL_GTAO_SLICES;
            f.dir_x[k][i] = cosf(phi);
            f.dir_y[k][i] = sinf(phi);
        }
    return f;
}

/* The cosine-weighted visible arc from 0 to horizon h within a slice whose projected normal is at
 * angle gamma from V: integral_0^h cos(t - gamma) |sin t| dt (the |sin t| of slicing about V). */
static float arc(float h, float gamma, float cos_gamma, float sin_gamma)
{
    return 0.25f * (-cosf(2.0f * h - gamma) + cos_gamma + 2.0f * h * sin_gamma);
}

/* The world point on the view ray through screen point (px, py) (pixel units, row 0 = bottom) that
 * lies on the plane of texel q (its position and normal). A sample is read from the nearest texel,
 * half a pixel off the slice at most; intersecting the slice's own ray with that texel's tangent
 * plane puts the point back on the slice, exactly for a planar surface. Without it, on a floor
 * seen at an angle, the rounding lifts half the samples above the floor's horizon and the maximum
 * keeps them: false occlusion of up to 8% (tests/unit/test_gtao.c, open floor). */
static vec3 on_slice(const gtao_frame *f, const sl_gbuffer_texel *q, float px, float py)
{
    vec3 ray = add(f->forward, add(scale(f->right, (px - f->half_width) / f->pixels_per_unit),
                                   scale(f->up, (py - f->half_height) / f->pixels_per_unit)));
    float along = dot(ray, q->normal);
    if (fabsf(along) < 1e-6f)
        return q->position;
    float s = dot(sub(q->position, f->eye), q->normal) / along;
    return s > 0.0f ? add(f->eye, scale(ray, s)) : q->position;
}

/* The highest horizon (largest cos to V) along screen direction (dx, dy) from pixel (x, y) out to
 * `pixels`: -1 when nothing within the radius rises above the view-perpendicular plane. */
static float horizon_cos(const sl_gbuffer *gb, const gtao_frame *f, int x, int y, vec3 P, vec3 V, float dx, float dy,
                         float pixels, float shift)
{
    float best = -1.0f;
    for (int s = 0; s < SL_GTAO_STEPS; s++) {
        float t = pixels * ((float)s + shift) / (float)SL_GTAO_STEPS;
        float px = (float)x + 0.5f + dx * t, py = (float)y + 0.5f + dy * t;
        int sx = (int)floorf(px), sy = (int)floorf(py);
        if ((sx == x && sy == y) || sx < 0 || sy < 0 || sx >= gb->width || sy >= gb->height)
            continue;
        const sl_gbuffer_texel *q = sl_gbuffer_at(gb, sx, sy);
        if (!sl_gbuffer_covered(q))
            continue;
        vec3 d = sub(on_slice(f, q, px, py), P);
        float l2 = dot(d, d);
        if (l2 > f->radius2 || l2 < 1e-20f)
            continue;
        float c = dot(d, V) / sqrtf(l2);
        best = c > best ? c : best;
    }
    return best;
}

static float texel_ao(const sl_gbuffer *gb, const gtao_frame *f, int x, int y)
{
    const sl_gbuffer_texel *t = sl_gbuffer_at(gb, x, y);
    if (!sl_gbuffer_covered(t))
        return 1.0f;
    vec3 P = t->position;
    vec3 V = normalize(sub(f->eye, P));
    vec3 N = sl_lighting_facing_normal(t->normal, V);
    float depth = dot(sub(P, f->eye), f->forward);
    if (!(depth > 0.0f))
        return 1.0f;
    float pixels = f->radius * f->pixels_per_unit / depth;
    if (pixels > f->max_pixels)
        pixels = f->max_pixels;
    if (pixels < 1.0f) /* the radius is under a pixel here: nothing to read */
        return 1.0f;
    int k = bayer4[(x & 3) + 4 * (y & 3)];
    float shift = ((float)bayer4[((x + 2) & 3) + 4 * ((y + 1) & 3)] + 0.5f) / GTAO_PATTERN;
    const float *cos_phi = f->dir_x[k], *sin_phi = f->dir_y[k];
    /* The slices turn evenly about V (the integral over the hemisphere is over slice angles about
     * V, not about the screen's axis, which an off-centre pixel sees tilted); each is marched along
     * its own direction's image on the screen. */
    vec3 b1 = normalize(sub(f->right, scale(V, dot(V, f->right))));
    vec3 b2 = cross(V, b1);
    vec4 clip = mat4_mul_vec4(f->view_proj, vec4(P.x, P.y, P.z, 1.0f));
    float step = 1e-3f * depth;
    float sum = 0.0f;
    for (int i = 0; i < SL_GTAO_SLICES; i++) {
        vec3 dir = add(scale(b1, cos_phi[i]), scale(b2, sin_phi[i]));
        vec3 axis = cross(dir, V);
        vec3 Q = add(P, scale(dir, step));
        vec4 cq = mat4_mul_vec4(f->view_proj, vec4(Q.x, Q.y, Q.z, 1.0f));
        float sx = (cq.x / cq.w - clip.x / clip.w) * f->half_width, sy = (cq.y / cq.w - clip.y / clip.w) * f->half_height;
        float sl = sqrtf(sx * sx + sy * sy);
        if (!(sl > 0.0f))
            continue;
        sx /= sl;
        sy /= sl;
        vec3 Np = sub(N, scale(axis, dot(N, axis)));
        float lp = length(Np);
        if (lp < 1e-6f)
            continue; /* the normal lies along the slice's axis: the slice sees none of its cosine */
        float gamma = atan2f(dot(Np, dir), dot(Np, V));
        float cos_gamma = cosf(gamma), sin_gamma = sinf(gamma);
        float c_pos = horizon_cos(gb, f, x, y, P, V, sx, sy, pixels, shift);
        float c_neg = horizon_cos(gb, f, x, y, P, V, -sx, -sy, pixels, shift);
        float h_pos = acosf(c_pos), h_neg = -acosf(c_neg);
        /* no horizon below the surface's own tangent plane */
        h_pos = gamma + fminf(h_pos - gamma, 0.5f * SL_PI);
        h_neg = gamma + fmaxf(h_neg - gamma, -0.5f * SL_PI);
        sum += lp * (arc(h_pos, gamma, cos_gamma, sin_gamma) + arc(h_neg, gamma, cos_gamma, sin_gamma));
    }
    float ao = sum / (float)SL_GTAO_SLICES;
    return ao < 0.0f ? 0.0f : ao > 1.0f ? 1.0f : ao;
}

/* The blur: each covered texel's AO becomes the mean over the 4x4 block around it (x - 1 .. x + 2,
 * so every pattern entry is in it once) of the texels on the same surface: covered, view depth
 * within GTAO_BLUR_DEPTH of its own and normal within GTAO_BLUR_NORMAL. Across an edge the
 * block holds fewer texels, never the other surface's. */
#define GTAO_BLUR_DEPTH 0.02f /* relative view-depth difference */
#define GTAO_BLUR_NORMAL 0.8f /* cosine between the normals */

static float blurred(const sl_gbuffer *gb, const gtao_frame *f, const float *ao, int x, int y)
{
    const sl_gbuffer_texel *c = sl_gbuffer_at(gb, x, y);
    float zc = dot(sub(c->position, f->eye), f->forward);
    float sum = 0.0f, n = 0.0f;
    for (int sy = y - 1; sy <= y + 2; sy++)
        for (int sx = x - 1; sx <= x + 2; sx++) {
            if (sx < 0 || sy < 0 || sx >= gb->width || sy >= gb->height)
                continue;
            const sl_gbuffer_texel *q = sl_gbuffer_at(gb, sx, sy);
            if (!sl_gbuffer_covered(q) || dot(q->normal, c->normal) < GTAO_BLUR_NORMAL)
                continue;
            float zq = dot(sub(q->position, f->eye), f->forward);
            if (fabsf(zq - zc) > GTAO_BLUR_DEPTH * zc)
                continue;
            sum += ao[(size_t)sy * (size_t)gb->width + (size_t)sx];
            n += 1.0f;
        }
    return n > 0.0f ? sum / n : 1.0f;
}

float sl_gtao_texel(const sl_gbuffer *gb, const sl_camera *cam, float radius, int x, int y)
{
    gtao_frame f = frame_of(gb, cam, radius);
    if (!sl_gbuffer_covered(sl_gbuffer_at(gb, x, y)))
        return 1.0f;
    int x0 = x - 1 < 0 ? 0 : x - 1, y0 = y - 1 < 0 ? 0 : y - 1;
    /* the raw values of the block around (x, y), where blurred() reads them */
    float *ao = calloc((size_t)gb->width * (size_t)gb->height, sizeof *ao);
    if (!ao)
        return 1.0f;
    for (int sy = y0; sy <= y + 2 && sy < gb->height; sy++)
        for (int sx = x0; sx <= x + 2 && sx < gb->width; sx++)
            ao[(size_t)sy * (size_t)gb->width + (size_t)sx] = texel_ao(gb, &f, sx, sy);
    float v = blurred(gb, &f, ao, x, y);
    free(ao);
    return v;
}

bool sl_gtao_apply(sl_gbuffer *gb, const sl_camera *cam, float radius, int threads, sl_error *err)
{
    if (!gb->extra)
        return sl_fail(err, SL_ERR_RANGE, "ambient occlusion: the G-buffer has no extra plane to write it into");
    if (!(radius > 0.0f) || !isfinite(radius))
        return sl_fail(err, SL_ERR_RANGE, "ambient occlusion: radius %g, expected a positive number", (double)radius);
    const int height = gb->height, width = gb->width;
    float *ao = malloc((size_t)width * (size_t)height * sizeof *ao);
    if (!ao)
        return sl_fail(err, SL_ERR_MEMORY, "ambient occlusion: out of memory for %dx%d", width, height);
    gtao_frame f = frame_of(gb, cam, radius);
#pragma omp parallel num_threads(sl_threads(threads))
    {
#pragma omp for schedule(dynamic, 4)
        for (int y = 0; y < height; y++)
            for (int x = 0; x < width; x++)
                ao[(size_t)y * (size_t)width + (size_t)x] = texel_ao(gb, &f, x, y);
#pragma omp for schedule(dynamic, 4)
        for (int y = 0; y < height; y++) {
            sl_gbuffer_extra *row = gb->extra + (size_t)y * (size_t)width;
            for (int x = 0; x < width; x++)
                if (sl_gbuffer_covered(sl_gbuffer_at(gb, x, y)))
                    row[x].occlusion *= blurred(gb, &f, ao, x, y);
        }
    }
    free(ao);
    return true;
}

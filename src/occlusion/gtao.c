/* gtao.c - ground-truth-based ambient occlusion over the G-buffer (the method and its limits:
 * gtao.h). Three passes, rows to threads in each: the tangent planes of the half-resolution grid
 * (planes_of), the raw samples on that grid (2 * SL_GTAO_SLICES * SL_GTAO_STEPS plane reads each,
 * all within SL_GTAO_MAX_SCREEN of the image height; the AO and the bent normal), and each
 * texel's blurred value multiplied into its occlusion and written with its bent normal into the
 * cone plane. Each of the last two has a plain per-texel form, the reference (texel_ao, blurred:
 * sl_gtao_texel runs them), and the frame's, the same expressions in vector loops over a run of a
 * row's texels, a lane a texel, with the same bits (march_span, blurred_span; tests/unit/test_gtao.c
 * holds the two to each other). shaders/gtao.frag and gtao_blur.frag are the GLSL twin, in the
 * same order. */
#include "gtao.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <softlight/lighting.h>

#include "core/threads.h"

/* The 4x4 ordered-dither matrix: each sample of a 4x4 block turns its slices and shifts its steps
 * by a different 16th, and the blur over the block (blurred) averages the 16 back into one
 * estimate with 16 x SL_GTAO_SLICES directions: banding traded for noise the blur removes. */
static const unsigned char bayer4[16] = {0, 8, 2, 10, 12, 4, 14, 6, 3, 11, 1, 9, 15, 7, 13, 5};
#define GTAO_PATTERN 16

/* What every pixel shares: the camera's frame and the radius in pixels at unit depth. */
typedef struct {
    sl_gtao_view view;
    float half_width, half_height; /* the image's centre, pixels */
    float radius, radius2;
    float max_pixels;
    /* cos and sin of each slice's angle about V, for each of the 16 turns */
    float dir_x[GTAO_PATTERN][SL_GTAO_SLICES], dir_y[GTAO_PATTERN][SL_GTAO_SLICES];
} gtao_frame;

sl_gtao_view sl_gtao_view_of(const sl_camera *cam, int height)
{
    sl_gtao_view v;
    v.eye = cam->eye;
    v.forward = normalize(sub(cam->target, cam->eye));
    v.right = normalize(cross(v.forward, cam->up));
    v.up = cross(v.right, v.forward);
    v.pixels_per_unit = 0.5f * (float)height / tanf(0.5f * cam->fovy_deg * (SL_PI / 180.0f));
    return v;
}

static gtao_frame frame_of(const sl_gbuffer *gb, const sl_camera *cam, float radius)
{
    gtao_frame f;
    f.view = sl_gtao_view_of(cam, gb->height);
    f.half_width = 0.5f * (float)gb->width;
    f.half_height = 0.5f * (float)gb->height;
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

/* acos to 7e-5 radians (Abramowitz and Stegun 4.4.45): the horizons' and the normal's angles
 * need no more, and the libm call was most of the pass's time. */
static inline float acos_fast(float x)
{
    float a = fabsf(x);
    a = a > 1.0f ? 1.0f : a;
    float r = sqrtf(1.0f - a) * (1.5707288f + a * (-0.2121144f + a * (0.0742610f - 0.0187293f * a)));
    return x < 0.0f ? SL_PI - r : r;
}

/* (int)floorf(v) for |v| < 2^31, from the truncation, which vectorizes where floorf does not. */
static inline int floor_int(float v)
{
    int t = (int)v;
    return (float)t > v ? t - 1 : t;
}

/* The cosine-weighted visible arc from the slice's view direction to its horizon on one side,
 * integral_0^h cos(t - n) |sin t| dt = (-cos(2h - n) + cos n + 2h sin n) / 4, for the horizon's
 * cosine c (side +1: h = acos c, side -1: h = -acos c) and the projected normal at angle n
 * (cos_n, sin_n), with no horizon below the surface's tangent plane: |h - n| <= pi/2. cos(2h - n)
 * comes from c by the double-angle identities, not from a cos call. h (side acos c) and whether
 * it is clamped come from the caller, which shares them with bent_arc. */
static inline float arc(float c, float side, float n, float cos_n, float sin_n, float h, bool clamped)
{
    /* both cases, then a select: no branch, so march_span's loop over texels vectorizes */
    float h_plane = n + side * 0.5f * SL_PI; /* clamped at the tangent plane, where cos(2h - n) = -cos n */
    float at_plane = 0.5f * (cos_n + h_plane * sin_n);
    float sin2 = 1.0f - c * c;
    float s = side * sqrtf(sin2 > 0.0f ? sin2 : 0.0f); /* sin h */
    float cos_2h = 2.0f * c * c - 1.0f, sin_2h = 2.0f * s * c;
    float open = 0.25f * (-(cos_2h * cos_n + sin_2h * sin_n) + cos_n + 2.0f * h * sin_n);
    return clamped ? at_plane : open;
}

/* The cosine-weighted mean direction of the same arc (the bent normal's share of it), as its
 * components along V and along the slice's direction:
 *   integral_0^h (cos t, sin t) cos(t - n) |sin t| dt
 *     = ((cos n (1 - cos^3 h) + sin n sin^3 h) / 3, cos n sin^3 h / 3 + sin n (2/3 - cos h + cos^3 h / 3)),
 * one expression for either side (for h < 0 it is the integral from h to 0). The horizon is
 * clamped at the tangent plane as arc() clamps it (h = n + side pi/2), by a select as there. */
static inline void bent_arc(float c, float side, float cos_n, float sin_n, bool clamped, float *along_v,
                            float *along_dir)
{
    float sin2 = 1.0f - c * c;
    float ch = clamped ? -side * sin_n : c;
    float sh = clamped ? side * cos_n : side * sqrtf(sin2 > 0.0f ? sin2 : 0.0f);
    float ch3 = ch * ch * ch, sh3 = sh * sh * sh;
    *along_v = (cos_n * (1.0f - ch3) + sin_n * sh3) * (1.0f / 3.0f);
    *along_dir = cos_n * sh3 * (1.0f / 3.0f) + sin_n * (2.0f / 3.0f - ch + ch3 * (1.0f / 3.0f));
}

/* What a sample reads of a texel: its tangent plane, (N, N.(P - eye)), 16 bytes where the texel
 * has 56, and of every other texel of every other row (the half-resolution grid, as the AO
 * itself): the reads reach up to SL_GTAO_MAX_SCREEN of the image height away, and the pass is
 * bound by them; a grid a quarter the texels' count, 1/14 of their bytes, keeps those rows in
 * cache. (0, 0, 0, 0) where nothing was drawn. The planes are a float array, PLANE floats a
 * plane (nx, ny, nz, w), so that march_span gathers them with 32-bit indices. */
enum { PLANE = 4 };

/* What the frame's blur (blurred_span) reads of the half-resolution grid, a channel at a time:
 * whether the sample's texel is covered (1 or 0), its normal (an empty texel's too: march_span
 * gives it as the empty texel's sample) and position (0 where empty), and the sample's AO and
 * bent normal. Each row has one empty entry (all 0) before its samples and two after, so the
 * 4 columns around any texel lie in the row in every channel, and one empty row follows the last
 * (row `height`), read in place of rows off the grid: the vector loops need no test of the image's
 * border, and the 56-byte texels are read once, not 16 times. */
enum { GRID_OK, GRID_NX, GRID_NY, GRID_NZ, GRID_PX, GRID_PY, GRID_PZ, GRID_AO, GRID_BX, GRID_BY, GRID_BZ, GRID_CHANNELS };
typedef struct {
    int stride, height; /* half width + 3, half height (rows: height + 1) */
    float *v;
} gtao_grid;

/* Row j of one channel (j = height: the empty row); column i of the half-resolution grid is
 * entry i + 1. */
static float *grid_row(const gtao_grid *g, int channel, int j)
{
    return g->v + ((size_t)channel * (size_t)(g->height + 1) + (size_t)j) * (size_t)g->stride;
}

/* The planes of the half-resolution grid: entry (i, j) is texel (2i, 2j)'s, for rows j0 .. j1 - 1;
 * with a grid, the same rows' texels (and its empty entries) in it. */
static void planes_of(const sl_gbuffer *gb, const gtao_frame *f, float *planes, gtao_grid *grid, int half_width,
                      int j0, int j1)
{
    for (int j = j0; j < j1; j++) {
        for (int i = 0; i < half_width; i++) {
            const sl_gbuffer_texel *t = sl_gbuffer_at(gb, 2 * i, 2 * j);
            float *p = planes + PLANE * ((size_t)j * (size_t)half_width + (size_t)i);
            bool covered = sl_gbuffer_covered(t);
            vec3 n = t->normal;
            p[0] = covered ? n.x : 0.0f;
            p[1] = covered ? n.y : 0.0f;
            p[2] = covered ? n.z : 0.0f;
            p[3] = covered ? dot(sub(t->position, f->view.eye), n) : 0.0f;
        }
        if (!grid)
            continue;
        for (int c = 0; c < GRID_CHANNELS; c++) {
            float *row = grid_row(grid, c, j);
            row[0] = row[half_width + 1] = row[half_width + 2] = 0.0f;
        }
        float *ok = grid_row(grid, GRID_OK, j) + 1, *nx = grid_row(grid, GRID_NX, j) + 1;
        float *ny = grid_row(grid, GRID_NY, j) + 1, *nz = grid_row(grid, GRID_NZ, j) + 1;
        float *px = grid_row(grid, GRID_PX, j) + 1, *py = grid_row(grid, GRID_PY, j) + 1;
        float *pz = grid_row(grid, GRID_PZ, j) + 1;
        for (int i = 0; i < half_width; i++) {
            const sl_gbuffer_texel *t = sl_gbuffer_at(gb, 2 * i, 2 * j);
            bool covered = sl_gbuffer_covered(t);
            ok[i] = covered ? 1.0f : 0.0f;
            nx[i] = t->normal.x; /* an empty texel's too: march_span's sample of it */
            ny[i] = t->normal.y;
            nz[i] = t->normal.z;
            px[i] = covered ? t->position.x : 0.0f;
            py[i] = covered ? t->position.y : 0.0f;
            pz[i] = covered ? t->position.z : 0.0f;
        }
    }
}

/* The highest horizons (largest cos to V) along screen direction (sx, sy) from pixel (x, y) and
 * along (-sx, -sy), out to `pixels`, into c[0] and c[1]: -1 where nothing within the radius rises
 * above the view-perpendicular plane.
 * A sample is the texel under the marched screen point, half a pixel off the slice at most; the
 * point used is where the slice's own view ray through the marched point meets that texel's
 * tangent plane, which is back on the slice, exactly for a planar surface. Without it, on a floor
 * seen at an angle, the rounding lifts half the samples above the floor's horizon and the maximum
 * keeps them: false occlusion of up to 8% (tests/unit/test_gtao.c, open floor). A texel seen
 * edge-on (the ray along its plane) is skipped.
 * Both sides' 2 x SL_GTAO_STEPS reads are taken together: their points and planes, then the ray,
 * the plane's point and its cosine for all of them in one vector loop (a lane a read: the
 * divisions and square roots of 8 reads in one instruction each; & rather than || and &&, so that
 * it has no branch), a skipped read's cosine -infinity; each side's maximum is then taken step by
 * step in order, so the result has the bits of a loop that skips. */
static void horizon_cos(const float *planes, int half_width, int half_height, const gtao_frame *f, int x, int y,
                        vec3 P, vec3 V, float sx, float sy, float pixels, float shift, float c[2])
{
    enum { READS = 2 * SL_GTAO_STEPS };
    float px[READS], py[READS], qnx[READS], qny[READS], qnz[READS], qw[READS], cos_v[READS];
    for (int r = 0; r < READS; r++) {
        int s = r % SL_GTAO_STEPS;
        float dx = r < SL_GTAO_STEPS ? sx : -sx, dy = r < SL_GTAO_STEPS ? sy : -sy;
        float t = pixels * ((float)s + shift) / (float)SL_GTAO_STEPS;
        px[r] = (float)x + 0.5f + dx * t;
        py[r] = (float)y + 0.5f + dy * t;
        int si = (int)floorf(0.5f * px[r]), sj = (int)floorf(0.5f * py[r]); /* the grid point's texel: (2si, 2sj) */
        /* a skipped read takes the zero plane, which fails the edge-on test below */
        static const float zero[PLANE] = {0.0f, 0.0f, 0.0f, 0.0f};
        const float *q = zero;
        if (!((2 * si == x && 2 * sj == y) || si < 0 || sj < 0 || si >= half_width || sj >= half_height))
            q = planes + PLANE * ((size_t)sj * (size_t)half_width + (size_t)si);
        qnx[r] = q[0];
        qny[r] = q[1];
        qnz[r] = q[2];
        qw[r] = q[3];
    }
#pragma omp simd
    for (int r = 0; r < READS; r++) {
        vec3 ray = add(f->view.forward, add(scale(f->view.right, (px[r] - f->half_width) / f->view.pixels_per_unit),
                                       scale(f->view.up, (py[r] - f->half_height) / f->view.pixels_per_unit)));
        float along = ray.x * qnx[r] + ray.y * qny[r] + ray.z * qnz[r];
        /* nothing drawn (a zero plane), or seen edge-on */
        bool keep = fabsf(along) > 1e-6f;
        float depth = qw[r] / along;
        keep &= depth > 0.0f;
        vec3 d = sub(add(f->view.eye, scale(ray, depth)), P);
        float l2 = dot(d, d);
        keep &= !(l2 > f->radius2) & !(l2 < 1e-20f);
        float cv = dot(d, V) / sqrtf(l2);
        cos_v[r] = keep ? cv : -INFINITY;
    }
    for (int side = 0; side < 2; side++) {
        float best = -1.0f;
        for (int s = 0; s < SL_GTAO_STEPS; s++) {
            float cv = cos_v[side * SL_GTAO_STEPS + s];
            best = cv > best ? cv : best;
        }
        c[side] = best;
    }
}

/* A raw sample: the AO and the unnormalised bent normal (the cosine-weighted mean visible
 * direction), world space. */
typedef struct {
    float ao, bx, by, bz;
} gtao_sample;

/* The raw sample of texel (x, y), turned and shifted by entry (i, j) of the pattern. Where there is
 * nothing to read, AO 1 and the bent normal N (the texel's normal facing the eye). */
static gtao_sample texel_ao(const sl_gbuffer *gb, const float *planes, const gtao_frame *f, int x, int y, int i,
                            int j)
{
    const sl_gbuffer_texel *t = sl_gbuffer_at(gb, x, y);
    if (!sl_gbuffer_covered(t))
        return (gtao_sample){1.0f, t->normal.x, t->normal.y, t->normal.z};
    vec3 P = t->position;
    vec3 V = normalize(sub(f->view.eye, P));
    vec3 N = sl_lighting_facing_normal(t->normal, V);
    const gtao_sample open = {1.0f, N.x, N.y, N.z};
    float depth = dot(sub(P, f->view.eye), f->view.forward);
    if (!(depth > 0.0f))
        return open;
    float pixels = f->radius * f->view.pixels_per_unit / depth;
    if (pixels > f->max_pixels)
        pixels = f->max_pixels;
    if (pixels < 1.0f) /* the radius is under a pixel here: nothing to read */
        return open;
    int k = bayer4[(i & 3) + 4 * (j & 3)];
    float shift = ((float)bayer4[((i + 2) & 3) + 4 * ((j + 1) & 3)] + 0.5f) / GTAO_PATTERN;
    const float *cos_phi = f->dir_x[k], *sin_phi = f->dir_y[k];
    /* The slices turn evenly about V (the integral over the hemisphere is over slice angles about
     * V, not about the screen's axis, which an off-centre pixel sees tilted); each is marched along
     * its own direction's image on the screen. */
    vec3 b1 = normalize(sub(f->view.right, scale(V, dot(V, f->view.right))));
    vec3 b2 = cross(V, b1);
    vec3 E = sub(P, f->view.eye); /* P in the camera's frame: (xc, yc, depth) */
    float xc = dot(E, f->view.right), yc = dot(E, f->view.up);
    float sum = 0.0f;
    vec3 bent = vec3s(0.0f);
    for (int slice = 0; slice < SL_GTAO_SLICES; slice++) {
        vec3 dir = add(scale(b1, cos_phi[slice]), scale(b2, sin_phi[slice]));
        vec3 axis = cross(dir, V);
        /* the screen image of dir at P: the derivative of the projection (x / z, y / z) */
        float df = dot(dir, f->view.forward);
        float sx = dot(dir, f->view.right) * depth - xc * df, sy = dot(dir, f->view.up) * depth - yc * df;
        float sl = sqrtf(sx * sx + sy * sy);
        if (!(sl > 0.0f))
            continue;
        sx /= sl;
        sy /= sl;
        vec3 Np = sub(N, scale(axis, dot(N, axis)));
        float lp = length(Np);
        if (lp < 1e-6f)
            continue; /* the normal lies along the slice's axis: the slice sees none of its cosine */
        float cos_n = dot(Np, V) / lp, sin_n = dot(Np, dir) / lp;
        float n = (sin_n < 0.0f ? -1.0f : 1.0f) * acos_fast(cos_n);
        float horizons[2];
        horizon_cos(planes, (gb->width + 1) / 2, (gb->height + 1) / 2, f, x, y, P, V, sx, sy, pixels, shift, horizons);
        float c_pos = horizons[0], c_neg = horizons[1];
        /* each horizon's angle once, for the AO's arc and the bent normal's */
        float h_pos = acos_fast(c_pos), h_neg = -acos_fast(c_neg);
        bool clamp_pos = h_pos - n >= 0.5f * SL_PI, clamp_neg = -(h_neg - n) >= 0.5f * SL_PI;
        sum += lp * (arc(c_pos, 1.0f, n, cos_n, sin_n, h_pos, clamp_pos) +
                     arc(c_neg, -1.0f, n, cos_n, sin_n, h_neg, clamp_neg));
        float v_pos, d_pos, v_neg, d_neg;
        bent_arc(c_pos, 1.0f, cos_n, sin_n, clamp_pos, &v_pos, &d_pos);
        bent_arc(c_neg, -1.0f, cos_n, sin_n, clamp_neg, &v_neg, &d_neg);
        bent = add(bent, scale(add(scale(V, v_pos + v_neg), scale(dir, d_pos + d_neg)), lp));
    }
    /* unclamped: one sample's few slices over- or undershoot 1 on an open surface, and the blur's
     * mean over the pattern cancels that only if nothing was cut off */
    return (gtao_sample){sum / (float)SL_GTAO_SLICES, bent.x, bent.y, bent.z};
}

/* texel_ao for the half-resolution texels i0 .. i1 - 1 of row j (at most MARCH_SPAN), vectorized,
 * with the same bits: the frame's march; texel_ao stays the reference, which sl_gtao_texel runs
 * (tests/unit/test_gtao.c holds the two to the same bits). The texels come from the grid's
 * channels (planes_of wrote them: coverage, normal, position) and their samples go into its AO
 * and bent-normal channels. First, in one vector loop, which texels have something to read
 * (covered, in front of the eye, a radius of a pixel or more); the others take their open value
 * (AO 1; the facing normal, or an empty texel's own normal) and drop out, and the rest are packed
 * into lanes, structure-of-arrays form (about half of a shipped scene's texels are the
 * environment's: no lane is spent on them). Each stage of texel_ao is then one vector loop over
 * the lanes: the view vector, the facing normal and the slice frame; per slice, its direction,
 * screen direction and projected normal; per read (both sides' SL_GTAO_STEPS each, in texel_ao's
 * order), the plane's gather and the running maximum; per slice, the arcs. Every expression is
 * texel_ao's (and facing_normal's, lighting.c), term by term in the same order, its branches as
 * selects of both results: a skipped slice (no screen direction, a normal along its axis) marches
 * 0 pixels and adds nothing; a read off the grid or of the texel itself takes the zero plane
 * after the last (at PLANE * half_width * half_height), which fails the edge-on test as in
 * horizon_cos. */
enum { MARCH_SPAN = 64 };
static void march_span(const float *planes, const gtao_frame *f, const gtao_grid *g, int j, int i0, int i1)
{
    enum { S = MARCH_SPAN };
    const int n = i1 - i0, half_width = g->stride - 3, half_height = g->height;
    const int zero = half_width * half_height; /* the zero plane */
    const float *ok = grid_row(g, GRID_OK, j) + 1 + i0, *tnx = grid_row(g, GRID_NX, j) + 1 + i0;
    const float *tny = grid_row(g, GRID_NY, j) + 1 + i0, *tnz = grid_row(g, GRID_NZ, j) + 1 + i0;
    const float *tpx = grid_row(g, GRID_PX, j) + 1 + i0, *tpy = grid_row(g, GRID_PY, j) + 1 + i0;
    const float *tpz = grid_row(g, GRID_PZ, j) + 1 + i0;
    float *gao = grid_row(g, GRID_AO, j) + 1 + i0, *gbx = grid_row(g, GRID_BX, j) + 1 + i0;
    float *gby = grid_row(g, GRID_BY, j) + 1 + i0, *gbz = grid_row(g, GRID_BZ, j) + 1 + i0;
    const float ex = f->view.eye.x, ey = f->view.eye.y, ez = f->view.eye.z;
    const float fx = f->view.forward.x, fy = f->view.forward.y, fz = f->view.forward.z;
    const float rx = f->view.right.x, ry = f->view.right.y, rz = f->view.right.z;
    const float ux = f->view.up.x, uy = f->view.up.y, uz = f->view.up.z;
    const float radius_pixels = f->radius * f->view.pixels_per_unit, max_pixels = f->max_pixels;
    const float ppu = f->view.pixels_per_unit, half_w = f->half_width, half_h = f->half_height, r2 = f->radius2;
    /* per texel: its view depth, march length, whether it has something to read (0 or 1: int,
     * not bool, as the float lanes' masks take them) */
    float dep[S], pix[S];
    int live[S];
#pragma omp simd
    for (int m = 0; m < n; m++) {
        const float depth = (tpx[m] - ex) * fx + (tpy[m] - ey) * fy + (tpz[m] - ez) * fz;
        float pixels = radius_pixels / depth;
        pixels = pixels > max_pixels ? max_pixels : pixels;
        live[m] = (ok[m] > 0.0f) & (depth > 0.0f) & !(pixels < 1.0f);
        dep[m] = depth;
        pix[m] = pixels;
        /* the open sample, which a texel with something to read overwrites: AO 1, its own normal
         * (an empty texel's; a covered one's facing normal below) */
        gao[m] = 1.0f;
        gbx[m] = tnx[m];
        gby[m] = tny[m];
        gbz[m] = tnz[m];
    }
    /* per lane: the texel (its column), its position and normal, march length, shift and slice
     * angles; the view vector, the facing normal, the slice frame, the screen position of P; per
     * slice, its direction, screen direction, projected normal and horizons; the sums */
    int col[S], lanes = 0;
    float Px[S], Py[S], Pz[S], Tx[S], Ty[S], Tz[S], Lpix[S], Ldep[S], shift[S];
    float cphi[SL_GTAO_SLICES][S], sphi[SL_GTAO_SLICES][S];
    float Vx[S], Vy[S], Vz[S], Nx[S], Ny[S], Nz[S], b1x[S], b1y[S], b1z[S], b2x[S], b2y[S], b2z[S], xc[S], yc[S];
    float ao[S], bx[S], by[S], bz[S];
    float dx[S], dy[S], dz[S], scx[S], scy[S], lp[S], cos_n[S], sin_n[S], ang[S], best[2][S];
    int slice_ok[S];
    /* per lane, this read's texel in `planes`, its point on the half grid and the plane read */
    int read_at[S];
    float qx_at[S], qy_at[S], plane_at[4][S];
    for (int m = 0; m < n; m++) {
        if (!live[m]) {
            if (ok[m] > 0.0f) { /* covered, nothing to read: texel_ao's open value */
                vec3 P = vec3(tpx[m], tpy[m], tpz[m]);
                vec3 N = sl_lighting_facing_normal(vec3(tnx[m], tny[m], tnz[m]), normalize(sub(f->view.eye, P)));
                gbx[m] = N.x;
                gby[m] = N.y;
                gbz[m] = N.z;
            }
            continue;
        }
        const int c = lanes++, i = i0 + m, k = bayer4[(i & 3) + 4 * (j & 3)];
        col[c] = i;
        Px[c] = tpx[m];
        Py[c] = tpy[m];
        Pz[c] = tpz[m];
        Tx[c] = tnx[m];
        Ty[c] = tny[m];
        Tz[c] = tnz[m];
        Lpix[c] = pix[m];
        Ldep[c] = dep[m];
        shift[c] = ((float)bayer4[((i + 2) & 3) + 4 * ((j + 1) & 3)] + 0.5f) / GTAO_PATTERN;
        for (int sl = 0; sl < SL_GTAO_SLICES; sl++) {
            cphi[sl][c] = f->dir_x[k][sl];
            sphi[sl][c] = f->dir_y[k][sl];
        }
    }
#pragma omp simd
    for (int m = 0; m < lanes; m++) {
        const float px = Px[m], py = Py[m], pz = Pz[m], nx = Tx[m], ny = Ty[m], nz = Tz[m];
        /* V = normalize(eye - P) */
        const float vx0 = ex - px, vy0 = ey - py, vz0 = ez - pz;
        const float vinv = 1.0f / sqrtf(vx0 * vx0 + vy0 * vy0 + vz0 * vz0);
        const float vx = vx0 * vinv, vy = vy0 * vinv, vz = vz0 * vinv;
        /* N = facing_normal(normal, V) */
        const float len2 = nx * nx + ny * ny + nz * nz, ninv = 1.0f / sqrtf(len2);
        const float nnx = nx * ninv, nny = ny * ninv, nnz = nz * ninv;
        const float ndotv = nnx * vx + nny * vy + nnz * vz, bend = 0.01f - ndotv;
        const float ubx = nnx + vx * bend, uby = nny + vy * bend, ubz = nnz + vz * bend;
        const float uinv = 1.0f / sqrtf(ubx * ubx + uby * uby + ubz * ubz);
        const int has_n = len2 > 1e-30f, bent = ndotv < 0.01f;
        Vx[m] = vx;
        Vy[m] = vy;
        Vz[m] = vz;
        Nx[m] = has_n ? (bent ? ubx * uinv : nnx) : vx;
        Ny[m] = has_n ? (bent ? uby * uinv : nny) : vy;
        Nz[m] = has_n ? (bent ? ubz * uinv : nnz) : vz;
        /* P in the camera's frame */
        const float Ex = px - ex, Ey = py - ey, Ez = pz - ez;
        xc[m] = Ex * rx + Ey * ry + Ez * rz;
        yc[m] = Ex * ux + Ey * uy + Ez * uz;
        /* b1 = normalize(right - V (V.right)), b2 = V x b1 */
        const float vr = vx * rx + vy * ry + vz * rz;
        const float b1x0 = rx - vx * vr, b1y0 = ry - vy * vr, b1z0 = rz - vz * vr;
        const float binv = 1.0f / sqrtf(b1x0 * b1x0 + b1y0 * b1y0 + b1z0 * b1z0);
        const float b1xm = b1x0 * binv, b1ym = b1y0 * binv, b1zm = b1z0 * binv;
        b1x[m] = b1xm;
        b1y[m] = b1ym;
        b1z[m] = b1zm;
        b2x[m] = vy * b1zm - vz * b1ym;
        b2y[m] = vz * b1xm - vx * b1zm;
        b2z[m] = vx * b1ym - vy * b1xm;
        ao[m] = bx[m] = by[m] = bz[m] = 0.0f;
    }
    for (int sl = 0; sl < SL_GTAO_SLICES; sl++) {
#pragma omp simd
        for (int m = 0; m < lanes; m++) {
            const float c = cphi[sl][m], s = sphi[sl][m], vx = Vx[m], vy = Vy[m], vz = Vz[m];
            const float ddx = b1x[m] * c + b2x[m] * s, ddy = b1y[m] * c + b2y[m] * s, ddz = b1z[m] * c + b2z[m] * s;
            const float ax = ddy * vz - ddz * vy, ay = ddz * vx - ddx * vz, az = ddx * vy - ddy * vx;
            const float df = ddx * fx + ddy * fy + ddz * fz, depth = Ldep[m];
            const float sx = (ddx * rx + ddy * ry + ddz * rz) * depth - xc[m] * df;
            const float sy = (ddx * ux + ddy * uy + ddz * uz) * depth - yc[m] * df;
            const float slen = sqrtf(sx * sx + sy * sy);
            const float nx = Nx[m], ny = Ny[m], nz = Nz[m], na = nx * ax + ny * ay + nz * az;
            const float npx = nx - ax * na, npy = ny - ay * na, npz = nz - az * na;
            const float l = sqrtf(npx * npx + npy * npy + npz * npz);
            const int on = (slen > 0.0f) & !(l < 1e-6f);
            const float cn = (npx * vx + npy * vy + npz * vz) / l, sn = (npx * ddx + npy * ddy + npz * ddz) / l;
            slice_ok[m] = on;
            dx[m] = ddx;
            dy[m] = ddy;
            dz[m] = ddz;
            scx[m] = on ? sx / slen : 0.0f; /* a skipped slice marches nowhere */
            scy[m] = on ? sy / slen : 0.0f;
            lp[m] = l;
            cos_n[m] = cn;
            sin_n[m] = sn;
            ang[m] = (sn < 0.0f ? -1.0f : 1.0f) * acos_fast(cn);
            best[0][m] = best[1][m] = -1.0f;
        }
        /* horizon_cos: the reads one at a time, each in every lane: the texel a vector loop,
         * its plane read by plain loads (as reflection.c's march_lanes: on cores whose gathers
         * issue slowly the pass takes 0.92 of the time, the same bits), its horizon a vector loop */
        for (int r = 0; r < 2 * SL_GTAO_STEPS; r++) {
            const int side = r / SL_GTAO_STEPS, step = r % SL_GTAO_STEPS;
#pragma omp simd
            for (int m = 0; m < lanes; m++) {
                const int i = col[m];
                const float sx = side ? -scx[m] : scx[m], sy = side ? -scy[m] : scy[m];
                const float t = Lpix[m] * ((float)step + shift[m]) / (float)SL_GTAO_STEPS;
                const float qx = (float)(2 * i) + 0.5f + sx * t, qy = (float)(2 * j) + 0.5f + sy * t;
                const int si = floor_int(0.5f * qx), sj = floor_int(0.5f * qy);
                const bool in = !(si == i && sj == j) & (si >= 0) & (sj >= 0) & (si < half_width) & (sj < half_height);
                /* an int: at most PLANE * (SL_RASTER_MAX_SIZE / 2)^2 + PLANE floats */
                read_at[m] = PLANE * (in ? sj * half_width + si : zero);
                qx_at[m] = qx;
                qy_at[m] = qy;
            }
            for (int m = 0; m < lanes; m++) {
                const float *plane = &planes[read_at[m]];
                plane_at[0][m] = plane[0];
                plane_at[1][m] = plane[1];
                plane_at[2][m] = plane[2];
                plane_at[3][m] = plane[3];
            }
#pragma omp simd
            for (int m = 0; m < lanes; m++) {
                const float qx = qx_at[m], qy = qy_at[m];
                const float a = (qx - half_w) / ppu, b = (qy - half_h) / ppu;
                const float rayx = fx + (rx * a + ux * b), rayy = fy + (ry * a + uy * b), rayz = fz + (rz * a + uz * b);
                const float along = rayx * plane_at[0][m] + rayy * plane_at[1][m] + rayz * plane_at[2][m];
                const float depth = plane_at[3][m] / along;
                const float ddx = (ex + rayx * depth) - Px[m], ddy = (ey + rayy * depth) - Py[m];
                const float ddz = (ez + rayz * depth) - Pz[m];
                const float l2 = ddx * ddx + ddy * ddy + ddz * ddz;
                const bool keep = (fabsf(along) > 1e-6f) & (depth > 0.0f) & !(l2 > r2) & !(l2 < 1e-20f);
                const float cv = keep ? (ddx * Vx[m] + ddy * Vy[m] + ddz * Vz[m]) / sqrtf(l2) : -INFINITY;
                best[side][m] = cv > best[side][m] ? cv : best[side][m];
            }
        }
#pragma omp simd
        for (int m = 0; m < lanes; m++) {
            const float c_pos = best[0][m], c_neg = best[1][m], cn = cos_n[m], sn = sin_n[m], a = ang[m];
            const float h_pos = acos_fast(c_pos), h_neg = -acos_fast(c_neg);
            const bool clamp_pos = h_pos - a >= 0.5f * SL_PI, clamp_neg = -(h_neg - a) >= 0.5f * SL_PI;
            const float l = lp[m];
            const float sum = ao[m] + l * (arc(c_pos, 1.0f, a, cn, sn, h_pos, clamp_pos) +
                                           arc(c_neg, -1.0f, a, cn, sn, h_neg, clamp_neg));
            float v_pos, d_pos, v_neg, d_neg;
            bent_arc(c_pos, 1.0f, cn, sn, clamp_pos, &v_pos, &d_pos);
            bent_arc(c_neg, -1.0f, cn, sn, clamp_neg, &v_neg, &d_neg);
            const float vs = v_pos + v_neg, ds = d_pos + d_neg;
            const float bxs = bx[m] + (Vx[m] * vs + dx[m] * ds) * l, bys = by[m] + (Vy[m] * vs + dy[m] * ds) * l;
            const float bzs = bz[m] + (Vz[m] * vs + dz[m] * ds) * l;
            const int on = slice_ok[m];
            ao[m] = on ? sum : ao[m];
            bx[m] = on ? bxs : bx[m];
            by[m] = on ? bys : by[m];
            bz[m] = on ? bzs : bz[m];
        }
    }
    for (int m = 0; m < lanes; m++) {
        const int e = col[m] - i0;
        gao[e] = ao[m] / (float)SL_GTAO_SLICES;
        gbx[e] = bx[m];
        gby[e] = by[m];
        gbz[e] = bz[m];
    }
}

/* Half resolution: the raw AO is computed at every other texel of every other row, (2i, 2j), the
 * pattern indexed by (i, j); it reads the full-resolution planes. Each texel's AO is then the
 * mean over the 4 x 4 half-resolution block around it (i - 1 .. i + 2 with i = x / 2, so every
 * pattern entry is in it once) of the samples on the same surface as the texel: covered, within
 * SL_GTAO_BLUR_DEPTH of its view depth from its tangent plane, normal within SL_GTAO_BLUR_NORMAL. Across an edge the
 * block holds fewer samples, never the other surface's; a texel with none keeps its AO at 1. */

typedef struct {
    int width, height; /* (W + 1) / 2 x (H + 1) / 2 */
    gtao_sample *ao; /* the samples, for blurred() (NULL for the frame: march_span writes them into the grid) */
    gtao_grid *grid; /* the frame's, for blurred_span (NULL for one texel: blurred() reads the G-buffer) */
} gtao_half;

/* The texel's cone: the blurred AO (clamped to [0, 1]) in w, the mean of the same samples' bent
 * normals, normalised, in xyz (the texel's normal facing the eye where they cancel or there are none). */
static sl_vec4 blurred(const sl_gbuffer *gb, const gtao_frame *f, const gtao_half *h, int x, int y)
{
    const sl_gbuffer_texel *c = sl_gbuffer_at(gb, x, y);
    float zc = dot(sub(c->position, f->view.eye), f->view.forward);
    float sum = 0.0f, n = 0.0f;
    vec3 bent = vec3s(0.0f);
    int i0 = x / 2, j0 = y / 2;
    for (int j = j0 - 1; j <= j0 + 2; j++)
        for (int i = i0 - 1; i <= i0 + 2; i++) {
            if (i < 0 || j < 0 || i >= h->width || j >= h->height)
                continue;
            const sl_gbuffer_texel *q = sl_gbuffer_at(gb, 2 * i, 2 * j);
            if (!sl_gbuffer_covered(q) || dot(q->normal, c->normal) < SL_GTAO_BLUR_NORMAL)
                continue;
            /* the same surface: within a share of the view depth of the texel's tangent plane */
            if (fabsf(dot(sub(q->position, c->position), c->normal)) > SL_GTAO_BLUR_DEPTH * zc)
                continue;
            const gtao_sample *q_ao = &h->ao[(size_t)j * (size_t)h->width + (size_t)i];
            sum += q_ao->ao;
            bent = add(bent, vec3(q_ao->bx, q_ao->by, q_ao->bz));
            n += 1.0f;
        }
    float ao = n > 0.0f ? sum / n : 1.0f;
    ao = ao < 0.0f ? 0.0f : ao > 1.0f ? 1.0f : ao;
    float lb = length(bent);
    if (!(lb > 1e-20f))
        bent = sl_lighting_facing_normal(c->normal, normalize(sub(f->view.eye, c->position)));
    else
        bent = scale(bent, 1.0f / lb);
    return (sl_vec4){bent.x, bent.y, bent.z, ao};
}

/* blurred() for the texels x0 .. x1 - 1 of row y (x0 even), vectorized, with the same bits: the
 * frame's blur; blurred() stays the reference, which sl_gtao_texel runs (tests/unit/test_gtao.c
 * holds the two to the same bits). Texels 2m and 2m + 1 have the same block, half-resolution
 * columns m - 1 .. m + 2 (entries m .. m + 3 of the grid's rows), so the span's texels are split
 * into its even and its odd ones, each in structure-of-arrays form, and one vector loop over each
 * half runs a texel per lane, its 16 candidates unrolled inside in blurred()'s order (rows outer,
 * columns inner), each sum a select between itself and itself plus the candidate: every texel adds
 * the same values in the same order, and the sums stay in registers. The grid's empty entries and
 * empty row fail the coverage test, as blurred() skips samples off the grid or on empty texels.
 * The loop runs over each half's lanes from its first covered texel to its last (an empty
 * texel's cone is its normal and AO 1, which the lanes hold already): none on a row of the
 * environment. Most of its time is memory (perf annotate): the row's texels read, its cone and
 * occlusion written. */
enum { BLUR_SPAN = 256 }; /* texels, even */
static void blurred_span(const sl_gbuffer *gb, const gtao_frame *f, const gtao_half *h, int x0, int x1, int y,
                         sl_vec4 *cone, sl_gbuffer_extra *extra)
{
    enum { HALF = BLUR_SPAN / 2 };
    const int n = x1 - x0, count[2] = {(n + 1) / 2, n / 2};
    /* texel x0 + 2m + p at [p][m]: its normal, position, the depth test's limit, whether it is
     * covered; the sums, then the cone */
    float cnx[2][HALF], cny[2][HALF], cnz[2][HALF], cpx[2][HALF], cpy[2][HALF], cpz[2][HALF], lim[2][HALF];
    float sum[2][HALF], cnt[2][HALF], sbx[2][HALF], sby[2][HALF], sbz[2][HALF];
    int cov[2][HALF]; /* 0 or 1 */
    const sl_gbuffer_texel *texels = sl_gbuffer_at(gb, x0, y);
    const float ex = f->view.eye.x, ey = f->view.eye.y, ez = f->view.eye.z;
    const float fx = f->view.forward.x, fy = f->view.forward.y, fz = f->view.forward.z;
    /* each half's covered texels lie in lanes lo .. hi - 1: the vector loop runs over those
     * alone (none on a row of the environment), the others keep the empty texel's cone */
    int lo[2] = {count[0], count[1]}, hi[2] = {0, 0};
    for (int p = 0; p < 2; p++) {
        for (int m = 0; m < count[p]; m++) {
            const sl_gbuffer_texel *c = &texels[2 * m + p];
            const float px = c->position.x, py = c->position.y, pz = c->position.z;
            const int covered = c->depth < 1.0f; /* sl_gbuffer_covered */
            cnx[p][m] = sbx[p][m] = c->normal.x;
            cny[p][m] = sby[p][m] = c->normal.y;
            cnz[p][m] = sbz[p][m] = c->normal.z;
            cpx[p][m] = px;
            cpy[p][m] = py;
            cpz[p][m] = pz;
            lim[p][m] = SL_GTAO_BLUR_DEPTH * ((px - ex) * fx + (py - ey) * fy + (pz - ez) * fz);
            cov[p][m] = covered;
            lo[p] = covered && m < lo[p] ? m : lo[p];
            hi[p] = covered ? m + 1 : hi[p];
        }
    }
    /* the block's rows, a row off the grid read as the grid's empty row */
    const float *q[4][GRID_CHANNELS];
    for (int r = 0; r < 4; r++) {
        int j = y / 2 - 1 + r;
        for (int ch = 0; ch < GRID_CHANNELS; ch++)
            q[r][ch] = grid_row(h->grid, ch, j < 0 || j >= h->height ? h->height : j) + x0 / 2;
    }
    for (int p = 0; p < 2; p++) {
#pragma omp simd
        for (int m = lo[p]; m < hi[p]; m++) {
            const float nx = cnx[p][m], ny = cny[p][m], nz = cnz[p][m], px = cpx[p][m], py = cpy[p][m];
            const float pz = cpz[p][m], l = lim[p][m];
            float s = 0.0f, c = 0.0f, bx = 0.0f, by = 0.0f, bz = 0.0f;
#pragma GCC unroll 4
            for (int r = 0; r < 4; r++)
#pragma GCC unroll 4
                for (int di = 0; di < 4; di++) {
                    const int e = m + di;
                    /* blurred()'s dot products, term by term in the same order */
                    float dn = q[r][GRID_NX][e] * nx + q[r][GRID_NY][e] * ny + q[r][GRID_NZ][e] * nz;
                    float dd = (q[r][GRID_PX][e] - px) * nx + (q[r][GRID_PY][e] - py) * ny +
                               (q[r][GRID_PZ][e] - pz) * nz;
                    /* & rather than &&: no branch, so every load is unconditional and the loop vectorizes */
                    bool same = (q[r][GRID_OK][e] > 0.0f) & !(dn < SL_GTAO_BLUR_NORMAL) & !(fabsf(dd) > l);
                    float s1 = s + q[r][GRID_AO][e], c1 = c + 1.0f;
                    float bx1 = bx + q[r][GRID_BX][e], by1 = by + q[r][GRID_BY][e], bz1 = bz + q[r][GRID_BZ][e];
                    s = same ? s1 : s;
                    c = same ? c1 : c;
                    bx = same ? bx1 : bx;
                    by = same ? by1 : by;
                    bz = same ? bz1 : bz;
                }
            /* the mean, clamped, into sum; the bent normal normalised, its length into cnt for the
             * fallback */
            float mean = s / c;
            float ao = c > 0.0f ? mean : 1.0f;
            sum[p][m] = ao < 0.0f ? 0.0f : ao > 1.0f ? 1.0f : ao;
            float lb = sqrtf(bx * bx + by * by + bz * bz);
            float inv = 1.0f / lb;
            /* an empty texel's cone: its normal, AO 1 */
            const int covered = cov[p][m];
            sbx[p][m] = covered ? bx * inv : nx;
            sby[p][m] = covered ? by * inv : ny;
            sbz[p][m] = covered ? bz * inv : nz;
            cnt[p][m] = covered ? lb : 1.0f;
        }
    }
    for (int k = 0; k < n; k++) {
        const int p = k & 1, m = k >> 1;
        if (!cov[p][m]) {
            cone[x0 + k] = (sl_vec4){sbx[p][m], sby[p][m], sbz[p][m], 1.0f};
            continue;
        }
        vec3 bent = vec3(sbx[p][m], sby[p][m], sbz[p][m]);
        if (!(cnt[p][m] > 1e-20f)) { /* no samples, or bent normals that cancel */
            const sl_gbuffer_texel *c = &texels[k];
            bent = sl_lighting_facing_normal(c->normal, normalize(sub(f->view.eye, c->position)));
        }
        cone[x0 + k] = (sl_vec4){bent.x, bent.y, bent.z, sum[p][m]};
        extra[x0 + k].occlusion *= sum[p][m];
    }
}

/* The raw samples of rows j0 .. j1 - 1, columns i0 .. i1 - 1, one texel at a time (texel_ao):
 * sl_gtao_texel's, the reference; the frame marches its rows with march_span. */
static void half_rows(const sl_gbuffer *gb, const float *planes, const gtao_frame *f, gtao_half *h, int j0,
                      int j1, int i0, int i1)
{
    for (int j = j0; j < j1; j++)
        for (int i = i0; i < i1; i++)
            h->ao[(size_t)j * (size_t)h->width + (size_t)i] = texel_ao(gb, planes, f, 2 * i, 2 * j, i, j);
}

sl_vec4 sl_gtao_texel(const sl_gbuffer *gb, const sl_camera *cam, float radius, int x, int y)
{
    gtao_frame f = frame_of(gb, cam, radius);
    const sl_gbuffer_texel *t = sl_gbuffer_at(gb, x, y);
    sl_vec4 v = {t->normal.x, t->normal.y, t->normal.z, 1.0f};
    if (!sl_gbuffer_covered(t))
        return v;
    gtao_half h = {(gb->width + 1) / 2, (gb->height + 1) / 2, NULL, NULL};
    size_t n = (size_t)h.width * (size_t)h.height;
    h.ao = calloc(n, sizeof *h.ao);
    float *planes = malloc(PLANE * n * sizeof *planes);
    if (h.ao && planes) {
        planes_of(gb, &f, planes, NULL, h.width, 0, h.height);
        /* the samples of the block blurred() reads */
        int i0 = x / 2 - 1, j0 = y / 2 - 1;
        half_rows(gb, planes, &f, &h, j0 < 0 ? 0 : j0, j0 + 4 < h.height ? j0 + 4 : h.height, i0 < 0 ? 0 : i0,
                  i0 + 4 < h.width ? i0 + 4 : h.width);
        v = blurred(gb, &f, &h, x, y);
    }
    free(h.ao);
    free(planes);
    return v;
}

void sl_gtao_scratch_free(sl_gtao_scratch *s)
{
    free(s->planes);
    free(s->grid);
    memset(s, 0, sizeof *s);
}

/* s with room for `planes` and `grid` floats: kept when it has it, else freed and allocated
 * again (a frame's contents never carry over). */
static bool scratch_reserve(sl_gtao_scratch *s, size_t planes, size_t grid)
{
    if (s->planes && s->planes_floats >= planes && s->grid_floats >= grid)
        return true;
    sl_gtao_scratch_free(s);
    s->planes = malloc(planes * sizeof *s->planes);
    s->grid = malloc(grid * sizeof *s->grid);
    if (!s->planes || !s->grid) {
        sl_gtao_scratch_free(s);
        return false;
    }
    s->planes_floats = planes;
    s->grid_floats = grid;
    return true;
}

bool sl_gtao_apply(sl_gbuffer *gb, const sl_camera *cam, float radius, int threads, sl_gtao_scratch *scratch,
                   sl_error *err)
{
    if (!gb->extra)
        return sl_fail(err, SL_ERR_RANGE, "ambient occlusion: the G-buffer has no extra plane to write it into");
    if (!(radius > 0.0f) || !isfinite(radius))
        return sl_fail(err, SL_ERR_RANGE, "ambient occlusion: radius %g, expected a positive number", (double)radius);
    const int height = gb->height, width = gb->width;
    /* the samples go into the grid alone (march_span, for blurred_span): no h.ao */
    gtao_half h = {(width + 1) / 2, (height + 1) / 2, NULL, NULL};
    const size_t half_count = (size_t)h.width * (size_t)h.height;
    gtao_grid grid = {h.width + 3, h.height, NULL};
    sl_gtao_scratch own = {0}, *s = scratch ? scratch : &own;
    if (!gb->cone) /* the G-buffer frees it (sl_gbuffer_free, or a resize) */
        gb->cone = malloc((size_t)width * (size_t)height * sizeof *gb->cone);
    if (!gb->cone || !scratch_reserve(s, PLANE * (half_count + 1), /* and the zero plane */
                                      (size_t)GRID_CHANNELS * (size_t)grid.stride * (size_t)(grid.height + 1)))
        return sl_fail(err, SL_ERR_MEMORY, "ambient occlusion: out of memory for %dx%d", width, height);
    float *planes = s->planes;
    grid.v = s->grid;
    h.grid = &grid;
    for (int ch = 0; ch < GRID_CHANNELS; ch++)
        memset(grid_row(&grid, ch, grid.height), 0, (size_t)grid.stride * sizeof *grid.v);
    memset(planes + PLANE * half_count, 0, PLANE * sizeof *planes);
    gtao_frame f = frame_of(gb, cam, radius);
    /* Three loops, each needing the last one's rows around it; every one hands out small chunks
     * (dynamic), so a thread the system deschedules holds up the barrier for one chunk at most
     * (bench/busy.sh with AO_RADIUS). */
#pragma omp parallel num_threads(sl_threads(threads))
    {
#pragma omp for schedule(dynamic, 8)
        for (int j = 0; j < h.height; j++)
            planes_of(gb, &f, planes, &grid, h.width, j, j + 1);
#pragma omp for schedule(dynamic, 2)
        for (int j = 0; j < h.height; j++)
            for (int i = 0; i < h.width; i += MARCH_SPAN)
                march_span(planes, &f, &grid, j, i, i + MARCH_SPAN < h.width ? i + MARCH_SPAN : h.width);
#pragma omp for schedule(dynamic, 4)
        for (int y = 0; y < height; y++) {
            sl_gbuffer_extra *row = gb->extra + (size_t)y * (size_t)width;
            sl_vec4 *cone = gb->cone + (size_t)y * (size_t)width;
            for (int x = 0; x < width; x += BLUR_SPAN)
                blurred_span(gb, &f, &h, x, x + BLUR_SPAN < width ? x + BLUR_SPAN : width, y, cone, row);
        }
    }
    if (s == &own)
        sl_gtao_scratch_free(&own);
    return true;
}

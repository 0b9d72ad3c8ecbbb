/* test_env_lights.c - env lights (src/ibl/env_lights.h and the lighting shader's
 * specular_env_lights / env_lights_samples): the K brightest texels taken out of the environment
 * and summed exactly at their ground-truth nodes, the estimator sampling the residual.
 *
 *   decomposition   residual + lights put back = the environment, texel by texel; the clamp, the
 *                   order (brightest first, ties by index), the node directions and weights
 *                   against a closed form derived here; K >= texels, 1x1 and 2x1 maps, bad K
 *   exactness       an environment that is black but for its lights: the residual is 0, so the
 *                   specular IS the ground truth's sum (float rounding; where the lobe is narrow
 *                   enough that both split the texels into cells, within the two quadratures'
 *                   difference) for Phong alpha 1 .. 1e5 and GGX r 0.3 and 0.1, N.V down to
 *                   grazing, both G terms, both paths, any estimator; with rotation/intensity
 *   worth           the GGX default's ceiling: a sun's or the lamps' texels and no more, none
 *                   on a plateau or a constant map, never more than the ceiling
 *   black texels    K larger than the lit texels: the black texels taken must stay harmless
 *   mixed           a sky with a 30000x sun: much closer to the truth with K = 16 than without;
 *                   K = 0 is bit for bit the render without the feature
 *   paths           the plain port and the batched path agree with env lights on
 *   errors          options.env_lights > 0 without (or with mismatched) extracted lights */
#include "shading_fixtures.h"
#include "shading/lighting_internal.h"
#include "shading/lighting_trace.h"
#include "ibl/env_lights.h"
#include "shading/env_light_groups.h"

#include <stdio.h>

static const double PI_D = 3.14159265358979323846;

/* ---- environments made of texels ---- */

/* An environment from w x h texels (row 0 = v 0 = +Z), mip chain built. */
static void env_from_texels(sl_env *env, int w, int h, const vec3 *texels)
{
    sl_image img = {0};
    sl_error err;
    assert_true(sl_image_alloc(&img, w, h, 3, &err));
    memcpy(img.data, texels, (size_t)w * (size_t)h * sizeof(vec3));
    if (!sl_env_build(env, &img, 0, &err))
        fail_msg("sl_env_build: %s", err.msg);
    sl_image_free(&img);
}

typedef struct {
    int i, j;   /* column, row */
    vec3 color; /* radiance */
} hot_texel;

/* A smooth, strictly positive sky (luminance about 0.4 .. 0.7) at texel centres, or black (sky
 * false), plus hot texels. */
static vec3 *sky_texels(int w, int h, const hot_texel *hot, int nhot, bool sky)
{
    vec3 *t = calloc((size_t)w * (size_t)h, sizeof *t);
    assert_non_null(t);
    for (int j = 0; j < h; j++)
        for (int i = 0; i < w; i++) {
            vec3 d = sl_uv_to_dir(vec2(((float)i + 0.5f) / (float)w, ((float)j + 0.5f) / (float)h));
            t[(size_t)j * w + i] = sky ? vec3(0.6f + 0.3f * d.z, 0.5f + 0.1f * d.x, 0.9f - 0.2f * d.z + 0.1f * d.y)
                                       : vec3s(0.0f);
        }
    for (int k = 0; k < nhot; k++)
        t[(size_t)hot[k].j * w + hot[k].i] = hot[k].color;
    return t;
}

static double lum(vec3 c) { return fx_luminance(&c.x); }

/* The integral m of w over texel k = j W + i, in closed form (the specification's lat-long map,
 * derived here independently of src/ibl): column i spans phi in [p0, p1] = [pi - 2 pi (i+1)/W,
 * pi - 2 pi i/W], row j spans z = cos(theta) in [z1, z0] = [cos(pi (j+1)/H), cos(pi j/H)],
 * dw = dz dphi, w = (sqrt(1 - z^2) cos(phi), sqrt(1 - z^2) sin(phi), z):
 *   m.x = S (sin p1 - sin p0),  m.y = S (cos p0 - cos p1),  m.z = (z0^2 - z1^2) / 2 (p1 - p0),
 *   S = integral of sqrt(1 - z^2) dz = [(z sqrt(1 - z^2) + asin z) / 2] from z1 to z0. */
static void texel_moment(int W, int H, size_t k, double m[3])
{
    int i = (int)(k % (size_t)W), j = (int)(k / (size_t)W);
    double p0 = PI_D - 2.0 * PI_D * (i + 1) / W, p1 = PI_D - 2.0 * PI_D * i / W;
    double z0 = cos(PI_D * j / H), z1 = cos(PI_D * (j + 1) / H);
    double S = 0.5 * (z0 * sqrt(fmax(0.0, 1.0 - z0 * z0)) + asin(z0)) -
               0.5 * (z1 * sqrt(fmax(0.0, 1.0 - z1 * z1)) + asin(z1));
    m[0] = S * (sin(p1) - sin(p0));
    m[1] = S * (cos(p0) - cos(p1));
    m[2] = 0.5 * (z0 * z0 - z1 * z1) * (p1 - p0);
}

static double norm3(const double m[3]) { return sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]); }

/* The unit centroid direction of texel k, as float. */
static vec3 texel_dir(int W, int H, size_t k)
{
    double m[3];
    texel_moment(W, H, k, m);
    double n = norm3(m);
    return vec3((float)(m[0] / n), (float)(m[1] / n), (float)(m[2] / n));
}

/* ---- a. the decomposition ---- */

typedef struct {
    double y;
    size_t k;
} ranked_texel;

static int by_luminance_then_index(const void *a, const void *b)
{
    const ranked_texel *p = a, *q = b;
    if (p->y != q->y)
        return p->y > q->y ? -1 : 1;
    return (p->k > q->k) - (p->k < q->k);
}

/* Texels ranked by luminance (descending), ties by index: what the extraction must pick. */
static ranked_texel *rank_all(const vec3 *t, size_t n)
{
    ranked_texel *r = malloc(n * sizeof *r);
    assert_non_null(r);
    for (size_t k = 0; k < n; k++)
        r[k] = (ranked_texel){lum(t[k]), k};
    qsort(r, n, sizeof *r, by_luminance_then_index);
    return r;
}

/* Every property of an extraction from texels `t` (W x H) with `K` requested, all texels having
 * a direction: order, clamp, directions, put-back, untouched texels, residual mips, share. */
static void check_extraction(const sl_env_lights *el, const vec3 *t, int W, int H, int K)
{
    const size_t n = (size_t)W * (size_t)H;
    ranked_texel *r = rank_all(t, n);
    const int want = K < (int)n ? K : (int)n;
    assert_int_equal(el->count, want);
    double clamp = want < (int)n ? r[want].y : 0.0;
    if (fabs(el->clamp - clamp) > 1e-7 * clamp)
        fail_msg("clamp %.9g, expected %.9g (the %d-th brightest texel's luminance): off by %.3g", (double)el->clamp,
                 clamp, want + 1, (double)el->clamp - clamp);
    assert_int_equal(el->residual.level_count, (int)floor(log2((double)(W > H ? W : H))) + 1);
    assert_int_equal(el->residual.levels[0].width, W);
    assert_int_equal(el->residual.levels[0].height, H);
    const vec3 *res = el->residual.levels[0].texels;
    unsigned char *taken = calloc(n, 1);
    assert_non_null(taken);
    double taken_power = 0.0, total_power = 0.0;
    for (int j = 0; j < el->count; j++) {
        size_t k = el->texel[j];
        if (k != r[j].k)
            fail_msg("light %d is texel %zu (luminance %.9g), expected texel %zu (luminance %.9g)", j, k, lum(t[k]),
                     r[j].k, r[j].y);
        taken[k] = 1;
        double m[3];
        texel_moment(W, H, k, m);
        double w = norm3(m);
        /* direction: the unit centroid */
        for (int c = 0; c < 3; c++)
            if (fabs((double)(&el->dir[j].x)[c] - m[c] / w) > 2e-7)
                fail_msg("light %d (texel %zu): dir[%d] = %.9g, centroid %.9g: off by %.3g", j, k, c,
                         (double)(&el->dir[j].x)[c], m[c] / w, (double)(&el->dir[j].x)[c] - m[c] / w);
        /* residual r = L clamp / Y(L), and r + radiance / |m| = L to float rounding */
        double keep = clamp / lum(t[k]);
        for (int c = 0; c < 3; c++) {
            double L = (double)(&t[k].x)[c], rc = (double)(&res[k].x)[c];
            double back = rc + (double)(&el->radiance[j].x)[c] / w;
            if (fabs(rc - L * keep) > 1e-6 * L * keep + 1e-30)
                fail_msg("light %d (texel %zu) channel %d: residual %.9g, expected L clamp / Y = %.9g: off by %.3g", j, k,
                         c, rc, L * keep, rc - L * keep);
            if (fabs(back - L) > 1e-6 * L + 1e-30)
                fail_msg("light %d (texel %zu) channel %d: residual + radiance / |m| = %.9g, texel %.9g: off by %.3g "
                         "(relative %.3g)",
                         j, k, c, back, L, back - L, (back - L) / L);
        }
        taken_power += lum(el->radiance[j]);
    }
    /* untouched texels bit for bit; the residual's brightest texel is the clamp */
    double max_y = 0.0;
    for (size_t k = 0; k < n; k++) {
        if (!taken[k] && memcmp(&res[k], &t[k], sizeof(vec3)) != 0)
            fail_msg("texel %zu was not extracted but changed: (%.9g %.9g %.9g) -> (%.9g %.9g %.9g)", k, (double)t[k].x,
                     (double)t[k].y, (double)t[k].z, (double)res[k].x, (double)res[k].y, (double)res[k].z);
        max_y = fmax(max_y, lum(res[k]));
        double m[3];
        texel_moment(W, H, k, m);
        total_power += lum(t[k]) * norm3(m);
    }
    if (fabs(max_y - clamp) > 1e-6 * clamp)
        fail_msg("residual's largest luminance %.9g, clamp %.9g: off by %.3g", max_y, clamp, max_y - clamp);
    /* the mips are the residual's: no level holds anything brighter than the clamp */
    for (int l = 1; l < el->residual.level_count; l++) {
        const sl_env_level *lv = &el->residual.levels[l];
        for (size_t k = 0; k < (size_t)lv->width * (size_t)lv->height; k++)
            if (lum(lv->texels[k]) > clamp * (1.0 + 1e-5) + 1e-30)
                fail_msg("residual level %d texel %zu: luminance %.9g above the clamp %.9g (mips of the environment "
                         "instead of the residual?)",
                         l, k, lum(lv->texels[k]), clamp);
    }
    double share = taken_power / total_power;
    if (fabs(el->share - share) > 1e-5 * share + 1e-12)
        fail_msg("share %.9g, expected %.9g (taken / total luminous power): off by %.3g", el->share, share,
                 el->share - share);
    free(taken);
    free(r);
}

static void test_decomposition(void **state)
{
    (void)state;
    enum { W = 64, H = 32 };
    /* hot texels of different colours, at the poles too, and a tie: texels 10*64+30 and
     * 10*64+31 have the same colour, 5th and 6th by luminance (656, 433, 414, 300, 250, 250,
     * 150, 3.2); with K = 5 the lower index is the 5th light and the other sets the clamp */
    const hot_texel hot[] = {
        {10, 5, {500, 400, 300}},  {40, 20, {50, 900, 20}}, {3, 31, {2000, 10, 10}},
        {63, 0, {100, 100, 800}},  {20, 16, {300, 300, 300}}, {31, 10, {250, 250, 250}},
        {30, 10, {250, 250, 250}}, {50, 25, {4, 3, 2}},
    };
    vec3 *t = sky_texels(W, H, hot, 8, true);
    sl_env env;
    env_from_texels(&env, W, H, t);
    sl_error err;
    const int counts[] = {1, 5, 6, 7, 8, 33, 64};
    for (int c = 0; c < 7; c++) {
        sl_env_lights el;
        if (!sl_env_lights_extract(&el, &env, counts[c], 0, &err))
            fail_msg("extract %d: %s", counts[c], err.msg);
        check_extraction(&el, t, W, H, counts[c]);
        if (counts[c] == 5) {
            assert_int_equal(el.texel[4], 10 * W + 30);
            assert_near(el.clamp, 250.0, 250.0 * 1e-6);
        }
        if (counts[c] == 6)
            assert_int_equal(el.texel[5], 10 * W + 31);
        /* deterministic: the same call gives the same bits */
        sl_env_lights again;
        assert_true(sl_env_lights_extract(&again, &env, counts[c], 0, &err));
        assert_int_equal(again.count, el.count);
        assert_memory_equal(again.dir, el.dir, sizeof el.dir);
        assert_memory_equal(again.radiance, el.radiance, sizeof el.radiance);
        assert_memory_equal(again.texel, el.texel, sizeof el.texel);
        assert_memory_equal(again.residual.levels[0].texels, el.residual.levels[0].texels, sizeof(vec3) * W * H);
        sl_env_lights_free(&again);
        sl_env_lights_free(&el);
        assert_int_equal(el.count, 0);
        assert_int_equal(el.residual.level_count, 0);
    }
    /* bad counts fail with a range error and leave nothing behind */
    const int bad[] = {0, -1, SL_ENV_LIGHTS_MAX + 1};
    for (int b = 0; b < 3; b++) {
        sl_env_lights el;
        err = (sl_error){0};
        assert_false(sl_env_lights_extract(&el, &env, bad[b], 0, &err));
        assert_int_equal(err.code, SL_ERR_RANGE);
        assert_non_null(strstr(err.msg, "env lights"));
        assert_int_equal(el.count, 0);
        assert_int_equal(el.residual.level_count, 0);
    }
    sl_env none = {0};
    sl_env_lights el;
    assert_false(sl_env_lights_extract(&el, &none, 4, 0, &err));
    sl_env_free(&env);
    free(t);
}

/* The GGX default's ceiling (sl_env_lights_extract_worth): a sun of 3 texels or 4 lamps in a
 * sky give those texels and nothing else, bit for bit what asking for that count gives; a plateau
 * (a softbox of 72 texels within 1% of each other) and a constant map give none and no residual;
 * a ramp of 80 peaks halving each time stops at the ceiling or where the rest take under 2%. */
static void test_worth_their_cost(void **state)
{
    (void)state;
    enum { W = 64, H = 32 };
    sl_error err;
    const hot_texel sun[] = {{10, 5, {9000, 8000, 7000}}, {11, 5, {6000, 5000, 4000}}, {10, 6, {3000, 2500, 2000}}};
    const hot_texel lamps[] = {{3, 20, {1e4, 9e3, 8e3}}, {30, 18, {5e3, 5e3, 5e3}}, {45, 17, {3e3, 2e3, 1e3}},
                               {60, 22, {2e3, 2e3, 2e3}}};
    struct {
        const hot_texel *hot;
        int count;
    } peaks[] = {{sun, 3}, {lamps, 4}};
    for (int c = 0; c < 2; c++) {
        vec3 *t = sky_texels(W, H, peaks[c].hot, peaks[c].count, true);
        sl_env env;
        env_from_texels(&env, W, H, t);
        sl_env_lights worth, asked;
        assert_true(sl_env_lights_extract_worth(&worth, &env, SL_ENV_LIGHTS_MAX, 0, &err));
        assert_int_equal(worth.count, peaks[c].count);
        assert_true(sl_env_lights_extract(&asked, &env, peaks[c].count, 0, &err));
        assert_memory_equal(worth.radiance, asked.radiance, sizeof worth.radiance);
        assert_memory_equal(worth.texel, asked.texel, sizeof worth.texel);
        assert_memory_equal(worth.residual.levels[0].texels, asked.residual.levels[0].texels, sizeof(vec3) * W * H);
        sl_env_lights_free(&worth);
        sl_env_lights_free(&asked);
        sl_env_free(&env);
        free(t);
    }
    /* a softbox: 12 x 6 texels at 100 within +-0.5%, on the sky */
    vec3 *t = sky_texels(W, H, NULL, 0, true);
    for (int j = 8; j < 14; j++)
        for (int i = 20; i < 32; i++)
            t[j * W + i] = vec3s(100.0f * (1.0f + 0.005f * sinf(1.7f * (float)(i * 7 + j))));
    sl_env env;
    env_from_texels(&env, W, H, t);
    sl_env_lights el;
    assert_true(sl_env_lights_extract_worth(&el, &env, SL_ENV_LIGHTS_MAX, 0, &err));
    assert_int_equal(el.count, 0);
    assert_int_equal(el.residual.level_count, 0);
    sl_env_free(&env);
    /* a constant map */
    for (int k = 0; k < W * H; k++)
        t[k] = vec3s(2.0f);
    env_from_texels(&env, W, H, t);
    assert_true(sl_env_lights_extract_worth(&el, &env, SL_ENV_LIGHTS_MAX, 0, &err));
    assert_int_equal(el.count, 0);
    sl_env_free(&env);
    /* 80 peaks 1000 / 2^k over a black map: a ceiling of 1, 2 or 3 takes them all; under the
     * most, the lights that take all but 2% of what 64 would take (2000 (1 - 2^-k) - 1000 k 2^-k:
     * 8 take 1961 of 2000, 7 take 1930) */
    for (int k = 0; k < W * H; k++)
        t[k] = vec3s(k < 80 ? ldexpf(1000.0f, -k) : 0.0f);
    env_from_texels(&env, W, H, t);
    const int most[] = {1, 2, 3, SL_ENV_LIGHTS_MAX}, expect[] = {1, 2, 3, 8};
    for (int m = 0; m < 4; m++) {
        assert_true(sl_env_lights_extract_worth(&el, &env, most[m], 0, &err));
        assert_int_equal(el.count, expect[m]);
        sl_env_lights_free(&el);
    }
    sl_env_free(&env);
    free(t);
}

/* K at or above the texel count (a smooth 8x4 sky, every texel lit): everything is taken, the
 * clamp is 0 and the residual is black at every level; each light carries its whole texel. */
static void test_all_texels_taken(void **state)
{
    (void)state;
    enum { W = 8, H = 4 };
    vec3 *t = sky_texels(W, H, NULL, 0, true);
    sl_env env;
    env_from_texels(&env, W, H, t);
    sl_error err;
    const int counts[] = {W * H, W * H + 1, SL_ENV_LIGHTS_MAX};
    for (int c = 0; c < 3; c++) {
        sl_env_lights el;
        assert_true(sl_env_lights_extract(&el, &env, counts[c], 0, &err));
        check_extraction(&el, t, W, H, counts[c]);
        assert_int_equal(el.count, W * H);
        assert_near(el.clamp, 0.0, 0.0);
        assert_near(el.share, 1.0, 1e-6);
        for (int l = 0; l < el.residual.level_count; l++) {
            const sl_env_level *lv = &el.residual.levels[l];
            for (size_t k = 0; k < (size_t)lv->width * (size_t)lv->height; k++)
                if (lv->texels[k].x != 0.0f || lv->texels[k].y != 0.0f || lv->texels[k].z != 0.0f)
                    fail_msg("level %d texel %zu of the residual is (%g %g %g), expected 0", l, k,
                             (double)lv->texels[k].x, (double)lv->texels[k].y, (double)lv->texels[k].z);
        }
        sl_env_lights_free(&el);
    }
    free(t);
    sl_env_free(&env);
}

/* Degenerate maps. 1x1: the one texel's centroid is the integral of w over the sphere, 0: no
 * direction, so no light, and the residual is the map. 2x1: two hemispheres (columns 0 and 1:
 * phi in [0, pi] and [-pi, 0], centroids +y and -y, |integral of w| = pi each): the brighter is
 * the light, the other sets the clamp. */
static void test_tiny_maps(void **state)
{
    (void)state;
    sl_error err;
    sl_env env;
    vec3 one = vec3(3.0f, 2.0f, 1.0f);
    env_from_texels(&env, 1, 1, &one);
    sl_env_lights el;
    assert_true(sl_env_lights_extract(&el, &env, 1, 0, &err));
    assert_int_equal(el.count, 0);
    assert_int_equal(el.residual.level_count, 1);
    assert_memory_equal(el.residual.levels[0].texels, &one, sizeof one);
    sl_env_lights_free(&el);
    sl_env_free(&env);

    vec3 two[2] = {vec3(1.0f, 1.0f, 1.0f), vec3(5.0f, 0.5f, 0.25f)};
    env_from_texels(&env, 2, 1, two);
    assert_true(sl_env_lights_extract(&el, &env, 1, 0, &err));
    check_extraction(&el, two, 2, 1, 1);
    assert_int_equal(el.texel[0], 1);
    vec3 d = texel_dir(2, 1, 1);
    assert_near(el.dir[0].x, d.x, 1e-7);
    assert_near(el.dir[0].y, d.y, 1e-7);
    assert_near(el.dir[0].z, d.z, 1e-7);
    /* the hemisphere's |integral of w| is pi: the light is (L - r) pi */
    double keep = lum(two[0]) / lum(two[1]);
    assert_near(el.radiance[0].x, (5.0 - 5.0 * keep) * PI_D, 1e-5);
    sl_env_lights_free(&el);
    sl_env_free(&env);
}

/* ---- b. exactness: black but for the lights ---- */

/* Hot texels spread over the sphere, different colours and brightness, two of them in the rows
 * at the poles (wedges a split must cut along their narrow azimuth). */
static const hot_texel LAMPS[] = {
    {5, 4, {400, 300, 200}}, {20, 10, {30, 600, 40}}, {33, 15, {900, 900, 900}},  {47, 22, {70, 80, 1500}},
    {60, 27, {1000, 200, 50}}, {12, 29, {250, 250, 10}}, {40, 0, {600, 500, 400}}, {7, 31, {300, 400, 800}},
};
enum { LAMP_W = 64, LAMP_H = 32, LAMP_COUNT = 8 };

static vec3 rotz(vec3 d, double rad)
{
    double c = cos(rad), s = sin(rad);
    return vec3((float)(c * d.x - s * d.y), (float)(s * d.x + c * d.y), d.z);
}

/* A normal and a view (environment space) such that light direction d reflects about the half
 * vector H into V: N.d = nv, and H is N tilted by gamma out of the plane of N and d (so d.H =
 * nv cos(gamma), N.H = cos(gamma), N.V = nv cos(2 gamma)). gamma = 0: the mirror set-up, D at
 * its peak. */
static void mirror_setup(vec3 d, float nv, float gamma, vec3 *N, vec3 *V)
{
    vec3 p = normalize(cross(d, normalize(vec3(0.3f, 0.5f, 0.8f))));
    float s = sqrtf(fmaxf(0.0f, 1.0f - nv * nv));
    vec3 n = normalize(add(scale(d, nv), scale(p, s)));
    vec3 q = normalize(cross(n, p)); /* perpendicular to n and d */
    vec3 h = normalize(add(scale(n, cosf(gamma)), scale(q, sinf(gamma))));
    *N = n;
    *V = normalize(sub(scale(h, 2.0f * dot(h, d)), d));
}

enum { ALPHA_COUNT = 8 };

typedef struct {
    double worst[ALPHA_COUNT];       /* per alpha */
    double worst_share[ALPHA_COUNT]; /* of the tolerance */
    int shaded;
} exact_stats;

/* Phong exponents, then GGX r = 0.3 and 0.1 (the G-buffer's lobe parameter -1 - r) */
static const float ALPHAS[ALPHA_COUNT] = {1.0f, 10.0f, 100.0f, 1000.0f, 10000.0f, 1e5f, -1.3f, -1.1f};

/* A lobe parameter's Phong exponent, GGX's of equal peak */
static float phong_alpha(float alpha) { return alpha >= 0.0f ? alpha : sl_ggx_phong_equivalent(-1.0f - alpha); }

/* The float budget of the exact sum against the double ground truth, from two conditionings:
 *  - D = c (N.H)^alpha raises N.H's rounding to the power alpha: N.H near 1 computed a few ulp
 *    (1.2e-7 above 1, 6e-8 below) off, from N and V turned into environment space,
 *    normalize(w + V) and the dot, moves D by alpha times that (GLSL has the same floats).
 *    Measured worst: alpha * 2 ulp above 1 (+2.4% at 1e5: N.H computed 1 + 2.4e-7 at the peak);
 *  - at grazing view w + V is short (|w + V| = 2 N.V at the mirror set-up), so V's rounding
 *    (1e-7, recomputed from the eye) turns H by 1e-7 / (2 N.V) and L.H = N.V by as much: the
 *    G term 1 / (L.H)^2 moves by 1e-7 / (N.V)^2 relative (measured 6e-5 at N.V = 0.03).
 * Allowed: 1e-4 + alpha * 4 ulp + 1.2e-7 / (N.V)^2. */
static double exact_tolerance(float alpha, double nv)
{
    return 1e-4 + 4.0 * 1.19e-7 * (double)alpha + 1.2e-7 / (nv * nv);
}

/* Where the lobe is narrower than a few texels, the env lights and the truth both split the
 * texels near R into cells, by one rule of width but not the same cells: the truth s x s, over
 * every texel within 6 widths, the env lights as many along each side as the lobe's width across
 * it asks, within 3 widths along each of the lobe's axes (core/options.h). The two quadratures
 * then differ by their own errors: measured worst 1.1% (alpha 10, G one, N.V 0.027, where the
 * lamp's texel straddles the horizon and the cells below it are dropped), 0.5% elsewhere. */
#define SPLIT_TOLERANCE 0.015

/* Shade the lamps map's specular at (N, V) in environment space for one alpha, both G terms
 * and both paths, against the truth. rot_deg and intensity: the environment's rotation and
 * intensity (the shader's options, the truth's query). */
static void exact_case(const sl_env *env, const sl_env_lights *el, const sl_ground_truth *gt, vec3 Ne, vec3 Ve,
                       int a, float rot_deg, float intensity, sl_estimator est, exact_stats *st)
{
    double rad = (double)rot_deg * PI_D / 180.0;
    vec3 N = rotz(Ne, rad), V = rotz(Ve, rad); /* world = Rz(rotation) env */
    const vec3 ks = vec3(0.9f, 0.6f, 0.3f);
    for (int g = 0; g < 2; g++) {
        const bool ggx = ALPHAS[a] < 0.0f;
        sl_gt_query q = {.n = N, .v = V, .kd = vec3s(0.0f), .ks = ks, .alpha = ggx ? 0.0 : ALPHAS[a], .ggx = ggx,
                         .roughness = ggx ? -1.0 - ALPHAS[a] : 0.0,
                         .g = g ? SL_GT_G_ONE : SL_GT_G_INV_LH2, .rotation = rad,
                         .intensity = intensity};
        sl_gt_result r;
        sl_error err;
        if (!sl_ground_truth_shade(gt, &q, &r, &err))
            fail_msg("ground truth: %s", err.msg);
        double tmax = fmax(r.specular[0], fmax(r.specular[1], r.specular[2]));
        for (int plain = 0; plain < 2; plain++) {
            sl_lighting_options o = {.samples = 8, .no_diffuse = true, .estimator = est,
                                     .gterm = g ? SL_GTERM_ONE : SL_GTERM_INV_LH2, .plain = plain,
                                     .env_lights = LAMP_COUNT, .env_rotation_deg = rot_deg, .env_intensity = intensity};
            sl_lighting_desc d = {.options = o, .env = env, .eye = scale(V, 10.0f), .inv_view_proj = mat4_identity(),
                                  .width = 1, .height = 1, .env_lights = el};
            sl_lighting_uniforms *u = fx_uniforms_for(&d);
            vec3 c = fx_shade(u, fx_texel(N, vec3s(0.0f), ks, ALPHAS[a]));
            const bool split = sl_shade_env_light_split(u, Ne, Ve, ALPHAS[a]).cells > 1;
            free(u);
            double e = 0.0;
            for (int ch = 0; ch < 3; ch++)
                e = fmax(e, fabs((double)(&c.x)[ch] - r.specular[ch]) / tmax);
            /* the set-ups put a lamp in the lobe: the truth is far from 0 */
            double tol = exact_tolerance(phong_alpha(ALPHAS[a]), (double)dot(N, V)) + (split ? SPLIT_TOLERANCE : 0.0);
            if (!(tmax > 1e-3) || !(e <= tol))
                fail_msg("alpha %g, G %s, %s path, estimator %s, N.V %.4f, rotation %g, intensity %g: specular "
                         "(%.8g %.8g %.8g), ground truth (%.8g %.8g %.8g): relative error %.3g > %.3g",
                         (double)ALPHAS[a], g ? "one" : "inv-lh2", plain ? "plain" : "batched", sl_estimator_name(est),
                         (double)dot(N, V), (double)rot_deg, (double)intensity, (double)c.x, (double)c.y, (double)c.z,
                         r.specular[0], r.specular[1], r.specular[2], e, tol);
            st->worst[a] = fmax(st->worst[a], e);
            st->worst_share[a] = fmax(st->worst_share[a], e / tol);
            st->shaded++;
        }
    }
}

/* H off N by 0.75 / sqrt(alpha) (D down to about exp(-0.28) of its peak: the lobe's flank,
 * where D's slope in N.H is steepest relative to its value), at most 0.3 rad. */
static float off_mirror(float alpha) { return fminf(0.3f, 0.75f / sqrtf(phong_alpha(alpha))); }

typedef struct {
    sl_env env;
    sl_env_lights el;
    sl_ground_truth gt;
    vec3 *texels;
} lamps;

static int lamps_setup(void **state)
{
    lamps *l = calloc(1, sizeof *l);
    l->texels = sky_texels(LAMP_W, LAMP_H, LAMPS, LAMP_COUNT, false);
    env_from_texels(&l->env, LAMP_W, LAMP_H, l->texels);
    sl_error err;
    if (!sl_ground_truth_init(&l->gt, &l->env, &err) || !sl_env_lights_extract(&l->el, &l->env, LAMP_COUNT, 0, &err))
        return -1;
    *state = l;
    return 0;
}

static int lamps_teardown(void **state)
{
    lamps *l = *state;
    sl_env_lights_free(&l->el);
    sl_ground_truth_free(&l->gt);
    sl_env_free(&l->env);
    free(l->texels);
    free(l);
    return 0;
}

/* Every lamp at the mirror direction (H = N: D at its peak, where a sampled estimator at alpha
 * 1e5 reads a blur) and a lobe width off it, N.V from head-on to grazing (0.03; 0.01 is where
 * normals are bent). The residual is black, so the specular is the lights' sum alone and must
 * equal the ground truth's sum over the same texels (SPLIT_TOLERANCE where both split them). */
static void test_exact_on_lamps(void **state)
{
    lamps *l = *state;
    assert_int_equal(l->el.count, LAMP_COUNT);
    assert_near(l->el.clamp, 0.0, 0.0);
    const float nvs[] = {1.0f, 0.7f, 0.3f, 0.1f, 0.03f};
    exact_stats st = {0};
    for (int k = 0; k < LAMP_COUNT; k++) {
        vec3 d = texel_dir(LAMP_W, LAMP_H, (size_t)LAMPS[k].j * LAMP_W + LAMPS[k].i);
        for (int i = 0; i < 5; i++)
            for (int a = 0; a < ALPHA_COUNT; a++)
                for (int off = 0; off < 2; off++) {
                    vec3 N, V;
                    mirror_setup(d, nvs[i], off ? off_mirror(ALPHAS[a]) : 0.0f, &N, &V);
                    if (dot(N, V) < 0.02f) /* kept clear of the bending at 0.01 */
                        continue;
                    int pick = (k + i + a) % 3;
                    sl_estimator est = pick == 0 ? SL_ESTIMATOR_MICROFACET
                                                 : (pick == 1 ? SL_ESTIMATOR_SPEC : SL_ESTIMATOR_CONSISTENT);
                    exact_case(&l->env, &l->el, &l->gt, N, V, a, 0.0f, 1.0f, est, &st);
                }
    }
    for (int a = 0; a < ALPHA_COUNT; a++)
        print_message("alpha %-6g worst relative error vs ground truth %.3g (worst %.0f%% of the tolerance)\n",
                      (double)ALPHAS[a], st.worst[a], 100.0 * st.worst_share[a]);
    assert_true(st.shaded > 1000);
}

/* The exact part carries the environment's rotation and intensity: the same mirror set-ups with
 * the map turned by 37 degrees (and -120) and 2.5x (and 0.5x) brighter, against the truth with
 * the same rotation and intensity. Also the trace: with a black residual the specular is the
 * env lights' part alone, and the trace reports it and the lights it split. */
static void test_exact_rotation_intensity(void **state)
{
    lamps *l = *state;
    exact_stats st = {0};
    const float rots[2] = {37.0f, -120.0f}, gains[2] = {2.5f, 0.5f};
    for (int k = 0; k < LAMP_COUNT; k += 2) {
        vec3 d = texel_dir(LAMP_W, LAMP_H, (size_t)LAMPS[k].j * LAMP_W + LAMPS[k].i);
        for (int r = 0; r < 2; r++)
            for (int a = 0; a < ALPHA_COUNT; a++) {
                vec3 N, V;
                mirror_setup(d, r ? 0.2f : 0.8f, (k / 2 + a) % 2 ? off_mirror(ALPHAS[a]) : 0.0f, &N, &V);
                exact_case(&l->env, &l->el, &l->gt, N, V, a, rots[r], gains[r], SL_ESTIMATOR_MICROFACET, &st);
            }
    }
    for (int a = 0; a < ALPHA_COUNT; a++)
        print_message("rotated: alpha %-6g worst relative error %.3g\n", (double)ALPHAS[a], st.worst[a]);
    /* trace, both paths: the samples read the black residual, so specular = env lights' part */
    vec3 d = texel_dir(LAMP_W, LAMP_H, (size_t)LAMPS[2].j * LAMP_W + LAMPS[2].i);
    vec3 N, V;
    mirror_setup(d, 0.5f, 0.05f, &N, &V);
    sl_gbuffer_texel t = fx_texel(N, vec3s(0.0f), vec3s(0.5f), 300.0f);
    sl_gbuffer gb = {.width = 1, .height = 1, .texels = &t};
    sl_lighting_trace *tr = malloc(sizeof *tr);
    assert_non_null(tr);
    for (int plain = 0; plain < 2; plain++) {
        sl_error err;
        sl_lighting_desc desc = {.options = {.samples = 16, .no_diffuse = true, .plain = plain, .env_lights = LAMP_COUNT},
                                 .env = &l->env, .eye = scale(V, 10.0f), .inv_view_proj = mat4_identity(), .width = 1,
                                 .height = 1, .env_lights = &l->el};
        sl_lighting_uniforms *u = fx_uniforms_for(&desc);
        assert_true(sl_lighting_trace_pixel(u, &gb, 0, 0, tr, &err));
        assert_int_equal(tr->env_light_count, LAMP_COUNT);
        assert_true(tr->env_lights.x > 0.0f);
        assert_memory_equal(&tr->env_lights, &tr->specular, sizeof(vec3));
        /* alpha 300 is narrower than this map's texels: the lamp near R is read over cells */
        assert_true(tr->env_lights_split >= 1 && tr->env_light_cells > 1);
        free(u);
    }
    free(tr);
}

/* K above the number of lit texels: the extra lights are black texels (luminance 0). They must
 * not poison the sum: the render stays finite and equal to the truth, and the residual black. */
static void test_black_texels_as_lights(void **state)
{
    lamps *l = *state;
    sl_error err;
    sl_env_lights el;
    assert_true(sl_env_lights_extract(&el, &l->env, LAMP_COUNT + 4, 0, &err));
    assert_true(el.count >= LAMP_COUNT && el.count <= LAMP_COUNT + 4);
    for (int j = 0; j < el.count; j++)
        if (!fx_finite3(el.radiance[j]) || !fx_finite3(el.dir[j]))
            fail_msg("light %d of %d (texel %zu, radiance (%.6g %.6g %.6g)) is not finite: a black texel's node weight "
                     "is 0 / 0",
                     j, el.count, el.texel[j], (double)el.radiance[j].x, (double)el.radiance[j].y,
                     (double)el.radiance[j].z);
    vec3 d = texel_dir(LAMP_W, LAMP_H, (size_t)LAMPS[0].j * LAMP_W + LAMPS[0].i);
    vec3 N, V;
    mirror_setup(d, 0.6f, 0.0f, &N, &V);
    sl_gt_query q = {.n = N, .v = V, .ks = vec3s(0.5f), .alpha = 50.0, .g = SL_GT_G_INV_LH2,
                     .intensity = 1.0};
    sl_gt_result r;
    assert_true(sl_ground_truth_shade(&l->gt, &q, &r, &err));
    for (int plain = 0; plain < 2; plain++) {
        sl_lighting_desc desc = {.options = {.samples = 8, .no_diffuse = true, .plain = plain, .env_lights = el.count},
                                 .env = &l->env, .eye = scale(V, 10.0f), .inv_view_proj = mat4_identity(), .width = 1,
                                 .height = 1, .env_lights = &el};
        sl_gbuffer_texel t = fx_texel(N, vec3s(0.0f), vec3s(0.5f), 50.0f);
        sl_gbuffer gb = {.width = 1, .height = 1, .texels = &t};
        sl_image out = {0};
        fx_render(&desc, &gb, 1, &out, NULL); /* no pixel repaired, every value finite */
        /* alpha 50 at N.V 0.6 is narrower than a few of this map's texels: both split */
        if (fabs(out.data[0] - r.specular[0]) > (1e-4 + SPLIT_TOLERANCE) * r.specular[0])
            fail_msg("%s path, %d env lights on %d lit texels: specular %.8g, truth %.8g", plain ? "plain" : "batched",
                     el.count, LAMP_COUNT, (double)out.data[0], r.specular[0]);
        sl_image_free(&out);
    }
    sl_env_lights_free(&el);
}

/* ---- c, d: a sky with a sun, on a sphere ---- */

/* A smooth sky and a 30000x sun of a few texels (a cone of 0.06 rad on 128x64 texels of 0.05). */
static vec3 sky_sun(vec3 d)
{
    vec3 sky = vec3(0.5f + 0.4f * d.z, 0.6f + 0.2f * d.x, 1.0f - 0.3f * d.z);
    return dot(d, normalize(vec3(0.3f, -0.8f, 0.5f))) > 0.998f ? vec3(30000.0f, 27000.0f, 22000.0f) : sky;
}

/* Specular nRMSE against the truth, luminance, over the covered pixels. */
static double nrmse(const sl_image *img, const double *truth, const unsigned char *mask)
{
    double e = 0.0, t = 0.0;
    for (int i = 0; i < img->width * img->height; i++) {
        if (!mask[i])
            continue;
        double s = fx_luminance(img->data + 3 * i);
        e += (s - truth[i]) * (s - truth[i]);
        t += truth[i] * truth[i];
    }
    return sqrt(e / t);
}

/* One sphere of alpha 1000 and one of 10000 reflecting the sun, N = 32, the microfacet
 * estimator, lod pdf with the distortion (the configuration of the top-down measurement). The
 * sampled sun is read through a blur of ~1 texel per sample cone and misses the truth's peak by
 * far; with K = 16 (the sun's texels and the sky's brightest) only the sky (luminance < 1.1) is
 * sampled. The sun's texels are as wide as these lobes or wider on this 128x64 map, so the env
 * lights read them over cells, as the truth does. Measured (alpha 1000, 10000): nRMSE without
 * 0.054 / 0.097, with 0.00028 / 0.00056, a factor of 194 / 175; asserted: at least 20x better and
 * below 0.01 (9x margins). */
static void test_sun_error_drops(void **state)
{
    (void)state;
    enum { W = 40, H = 40 };
    sl_env env;
    fx_env(&env, 128, 64, sky_sun);
    sl_ground_truth gt;
    sl_env_lights el;
    sl_error err;
    assert_true(sl_ground_truth_init(&gt, &env, &err));
    assert_true(sl_env_lights_extract(&el, &env, 16, 0, &err));
    print_message("sun: %d lights, clamp %.4g, share of the power %.4f\n", el.count, (double)el.clamp, el.share);
    assert_true(el.clamp < 2.0f); /* the whole sun was taken */
    sl_camera cam = {.eye = vec3(0, -3.2f, 0.4f), .target = vec3(0, 0, 0), .up = vec3(0, 0, 1), .fovy_deg = 40,
                     .znear = 0.1f, .zfar = 100};
    const float alphas[2] = {1000.0f, 10000.0f};
    for (int a = 0; a < 2; a++) {
        sl_synthetic_sphere s = {vec3(0, 0, 0), 1.0f, vec3s(0.0f), vec3(0.9f, 0.8f, 0.7f), alphas[a]};
        fx_frame f;
        fx_frame_spheres(&f, &env, &cam, &s, 1, W, H);
        const sl_gbuffer *gb = &f.gb;
        unsigned char *mask = fx_image_mask(gb);
        double *truth = calloc((size_t)W * H, sizeof *truth);
        assert_non_null(truth);
        for (int y = 0; y < H; y++)
            for (int x = 0; x < W; x++) {
                const sl_gbuffer_texel *t = sl_gbuffer_at(gb, x, y);
                if (!sl_gbuffer_covered(t))
                    continue;
                vec3 v = normalize(sub(cam.eye, t->position));
                sl_gt_query q = {.n = t->normal, .v = v, .ks = t->ks, .alpha = t->alpha, .g = SL_GT_G_INV_LH2,
                                 .intensity = 1.0};
                sl_gt_result r;
                assert_true(sl_ground_truth_shade(&gt, &q, &r, &err));
                truth[(H - 1 - y) * W + x] = 0.2126 * r.specular[0] + 0.7152 * r.specular[1] + 0.0722 * r.specular[2];
            }
        sl_lighting_options o = {.samples = 32, .estimator = SL_ESTIMATOR_MICROFACET, .lod_rule = SL_LOD_PDF,
                                 .distortion = true, .no_diffuse = true};
        sl_image off = {0}, on = {0}, off2 = {0};
        fx_frame_render(&f, o, &off);
        /* K = 0 with lights at hand: the feature is off, bit for bit */
        f.env_lights = &el;
        fx_frame_render(&f, o, &off2);
        assert_memory_equal(off.data, off2.data, sizeof(float) * 3 * W * H);
        o.env_lights = 16;
        fx_frame_render(&f, o, &on);
        double e_off = nrmse(&off, truth, mask), e_on = nrmse(&on, truth, mask);
        print_message("alpha %g: specular nRMSE vs ground truth without env lights %.4g, with 16: %.4g (%.0fx)\n",
                      (double)alphas[a], e_off, e_on, e_off / e_on);
        if (!(e_on * 20.0 < e_off) || !(e_on < 0.01))
            fail_msg("alpha %g: nRMSE with env lights %.4g, without %.4g: expected 20x lower and below 0.01",
                     (double)alphas[a], e_on, e_off);
        sl_image_free(&off);
        sl_image_free(&off2);
        sl_image_free(&on);
        free(truth);
        free(mask);
        fx_frame_teardown(&f);
    }
    sl_env_lights_free(&el);
    sl_ground_truth_free(&gt);
    sl_env_free(&env);
}

/* The plain port against the batched path with env lights on (three spheres: rough, glossy, a
 * metal of alpha 5000; the sky with the sun), over estimators, G terms, rotation and the
 * environment's rotation and intensity. Tolerances of test_lighting_fast's batched-vs-plain
 * (mean 3e-4, worst pixel 5e-3): the exact part differs only by D through the fast log2/exp2,
 * the residual's part also by the batched fetch's compact texels (measured mean 2.5e-5 ..
 * 9.5e-5, worst 2.2e-3). */
static void test_plain_vs_batched(void **state)
{
    (void)state;
    sl_env env;
    fx_env(&env, 128, 64, sky_sun);
    sl_env_lights el;
    sl_error err;
    assert_true(sl_env_lights_extract(&el, &env, 24, 0, &err));
    fx_frame f;
    fx_frame_setup(&f, &env, 72, 48, 5000.0f);
    f.env_lights = &el;
    const sl_lighting_options variants[] = {
        {.samples = 20},
        {.samples = 32, .estimator = SL_ESTIMATOR_MICROFACET, .lod_rule = SL_LOD_PDF, .distortion = true},
        {.samples = 24, .estimator = SL_ESTIMATOR_CONSISTENT, .gterm = SL_GTERM_ONE},
        {.samples = 16, .estimator = SL_ESTIMATOR_MICROFACET, .rotate = true, .frame = 4},
        {.samples = 24, .env_rotation_deg = 70.0f, .env_intensity = 2.0f, .no_diffuse = true},
    };
    for (size_t v = 0; v < sizeof variants / sizeof variants[0]; v++) {
        sl_image a = {0}, b = {0};
        sl_lighting_options o = variants[v];
        o.env_lights = 24;
        fx_frame_render(&f, o, &a);
        o.plain = true;
        fx_frame_render(&f, o, &b);
        double mx, mean;
        fx_image_rel_diff(&a, &b, &mx, &mean);
        print_message("variant %zu: batched vs plain with env lights: max rel %.3g, mean rel %.3g\n", v, mx, mean);
        if (!(mean < 3e-4) || !(mx < 5e-3))
            fail_msg("variant %zu: batched vs plain: max rel %.3g (allowed 5e-3), mean rel %.3g (allowed 3e-4)", v, mx,
                     mean);
        /* the feature is wired in both paths: the image differs from the one without */
        sl_image c = {0};
        o.env_lights = 0;
        fx_frame_render(&f, o, &c);
        fx_image_rel_diff(&b, &c, &mx, &mean);
        assert_true(mx > 1e-3);
        sl_image_free(&a);
        sl_image_free(&b);
        sl_image_free(&c);
    }
    fx_frame_teardown(&f);
    sl_env_lights_free(&el);
    sl_env_free(&env);
}

/* The lights grouped by map (shading/env_light_groups.h) against the loop over every light, sum
 * L_k max(N.l_k, 0), for normals all over the sphere and densely in the band where a group's
 * lights straddle the horizon (where the linear sum would be wrong): three clusters of lights a
 * few degrees wide, one of them 120 degrees wide (no cone: always the loop), and lights no map
 * covers. Relative to the group's total radiance, within float rounding. */
static void test_groups_match_loop(void **state)
{
    (void)state;
    vec4 dir[SL_ENV_LIGHTS_MAX], radiance[SL_ENV_LIGHTS_MAX];
    signed char map[SL_ENV_LIGHTS_MAX];
    const vec3 axes[4] = {normalize(vec3(0.3f, 0.2f, 0.9f)), normalize(vec3(-0.8f, 0.1f, 0.2f)),
                          normalize(vec3(0.1f, -1.0f, 0.05f)), normalize(vec3(0.5f, 0.5f, -0.7f))};
    const float spread[4] = {0.05f, 0.08f, 1.0f, 0.6f}; /* radians off the axis at most */
    const int count = 40;
    uint32_t seed = 7;
    float total = 0.0f;
    for (int j = 0; j < count; j++) {
        int c = j % 4;
        /* a direction within spread[c] of the axis: the axis turned about two random axes */
        float a = spread[c] * ((float)(seed = seed * 1664525u + 1013904223u) / 4294967296.0f);
        float phi = 6.2831853f * ((float)(seed = seed * 1664525u + 1013904223u) / 4294967296.0f);
        vec3 t = normalize(cross(axes[c], fabsf(axes[c].z) < 0.9f ? vec3(0.0f, 0.0f, 1.0f) : vec3(1.0f, 0.0f, 0.0f)));
        vec3 b = cross(axes[c], t);
        vec3 d = normalize(add(scale(axes[c], cosf(a)), scale(add(scale(t, cosf(phi)), scale(b, sinf(phi))), sinf(a))));
        dir[j] = vec4(d.x, d.y, d.z, 0.0f);
        radiance[j] = vec4(100.0f + (float)j, 50.0f, 10.0f * (float)(j % 7), 0.0f);
        total += radiance[j].x;
        map[j] = (signed char)(c < 3 ? c : -1); /* cluster 3: lights no map covers */
    }
    sl_env_light_groups g;
    sl_env_light_groups_build(&g, dir, radiance, count, map, 3);
    assert_int_equal(g.count, 4);
    int linear = 0, band = 0, below = 0;
    for (int n = 0; n < 20000; n++) {
        vec3 N;
        if (n % 2) { /* near a cluster's horizon: the axis turned 80 .. 100 degrees */
            int c = (n / 2) % 4;
            float a = (80.0f + 20.0f * (float)((n * 37) % 1000) / 1000.0f) * 0.017453293f, phi = 0.0173f * (float)n;
            vec3 t = normalize(cross(axes[c], vec3(0.3f, 0.7f, 0.2f))), b = cross(axes[c], t);
            N = normalize(add(scale(axes[c], cosf(a)), scale(add(scale(t, cosf(phi)), scale(b, sinf(phi))), sinf(a))));
        } else {
            float z = 1.0f - 2.0f * ((float)n + 0.5f) / 20000.0f, r = sqrtf(fmaxf(0.0f, 1.0f - z * z));
            N = vec3(r * cosf(2.39996323f * (float)n), r * sinf(2.39996323f * (float)n), z);
        }
        for (int k = 0; k < g.count; k++) {
            vec3 want = vec3s(0.0f);
            const sl_env_light_group *e = &g.group[k];
            for (int i = e->first; i < e->first + e->count; i++) {
                int j = g.member[i];
                want = add(want, scale(xyz(radiance[j]), fmaxf(dot(xyz(dir[j]), N), 0.0f)));
            }
            vec3 got = sl_env_light_group_irradiance(&g, k, dir, radiance, N);
            float na = dot(N, e->axis);
            linear += na >= e->sin_spread;
            below += na <= -e->sin_spread;
            band += na < e->sin_spread && na > -e->sin_spread;
            float err = fmaxf(fabsf(got.x - want.x), fmaxf(fabsf(got.y - want.y), fabsf(got.z - want.z)));
            if (!(err <= 2e-5f * total))
                fail_msg("normal %d, group %d: grouped (%g %g %g) against the loop's (%g %g %g)", n, k, (double)got.x,
                         (double)got.y, (double)got.z, (double)want.x, (double)want.y, (double)want.z);
        }
    }
    print_message("groups against the loop: %d linear, %d below, %d in the band\n", linear, below, band);
    assert_true(linear > 10000 && below > 10000 && band > 5000); /* every branch ran */
}

/* ---- errors ---- */

static void test_uniform_errors(void **state)
{
    (void)state;
    sl_env env, other;
    fx_env(&env, 32, 16, sky_sun);
    fx_env(&other, 64, 32, sky_sun);
    sl_env_lights el, el_other;
    sl_error err;
    assert_true(sl_env_lights_extract(&el, &env, 4, 0, &err));
    assert_true(sl_env_lights_extract(&el_other, &other, 4, 0, &err));
    sl_lighting_uniforms *u = malloc(sizeof *u);
    assert_non_null(u);
    sl_lighting_desc d = {.options = {.no_diffuse = true, .env_lights = 4}, .env = &env, .eye = vec3(0, 0, 10),
                          .inv_view_proj = mat4_identity(), .width = 1, .height = 1};
    /* asked for, none given */
    err = (sl_error){0};
    assert_false(sl_lighting_uniforms_init(u, &d, &err));
    assert_int_equal(err.code, SL_ERR_RANGE);
    assert_non_null(strstr(err.msg, "env lights"));
    print_message("no lights: %s\n", err.msg);
    /* extracted from another environment (another size) */
    d.env_lights = &el_other;
    err = (sl_error){0};
    assert_false(sl_lighting_uniforms_init(u, &d, &err));
    assert_non_null(strstr(err.msg, "env lights"));
    /* out of range */
    d.env_lights = &el;
    const int bad[2] = {-1, SL_ENV_LIGHTS_MAX + 1};
    for (int b = 0; b < 2; b++) {
        d.options.env_lights = bad[b];
        err = (sl_error){0};
        assert_false(sl_lighting_uniforms_init(u, &d, &err));
        assert_int_equal(err.code, SL_ERR_RANGE);
    }
    /* the right ones: the residual is what the samples read, the background keeps the map */
    d.options.env_lights = 4;
    assert_true(sl_lighting_uniforms_init(u, &d, &err));
    assert_ptr_equal(u->uEnvResidual, &el.residual);
    assert_ptr_equal(u->uEnv, &env);
    assert_int_equal(u->uEnvLightCount, 4);
    /* off: lights given but ignored */
    d.options.env_lights = 0;
    assert_true(sl_lighting_uniforms_init(u, &d, &err));
    assert_ptr_equal(u->uEnvResidual, &env);
    assert_int_equal(u->uEnvLightCount, 0);
    free(u);
    sl_env_lights_free(&el);
    sl_env_lights_free(&el_other);
    sl_env_free(&env);
    sl_env_free(&other);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_decomposition),
        cmocka_unit_test(test_all_texels_taken),
        cmocka_unit_test(test_worth_their_cost),
        cmocka_unit_test(test_tiny_maps),
        cmocka_unit_test_setup_teardown(test_exact_on_lamps, lamps_setup, lamps_teardown),
        cmocka_unit_test_setup_teardown(test_exact_rotation_intensity, lamps_setup, lamps_teardown),
        cmocka_unit_test_setup_teardown(test_black_texels_as_lights, lamps_setup, lamps_teardown),
        cmocka_unit_test(test_sun_error_drops),
        cmocka_unit_test(test_plain_vs_batched),
        cmocka_unit_test(test_groups_match_loop),
        cmocka_unit_test(test_uniform_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

/* checker.c - a G-buffer program: the material's diffuse colour as a checkerboard of two tones
 * on its texture coordinates (CELLS cells per unit, after the kd map's uv transform), each
 * pixel's value the pattern's mean over the pixel's footprint (its fwidth), so that cells
 * smaller than a pixel fade to the two tones' mean instead of aliasing. A kd map, where the
 * material has one, multiplies the pattern. GLSL twin: checker.frag, line for line.
 *
 *   softlight render scenes/textured.json --gbuffer-shader examples/shaders/checker.c -o checker.png */
#include <softlight/glsl.h>
#include <softlight/gbuffer_program.h>

#define CELLS 8.0f

/* The integral from 0 of the square wave that is +1 on [0, 1) and -1 on [1, 2): a triangle wave
 * of period 2, here on [0, 2]. */
static float wave_integral(float x) { return 1.0f - fabsf(1.0f - x); }

/* The square wave's mean over [x - w/2, x + w/2] (its box filter over the footprint): the
 * difference of its integral at the two ends, over the width. x is first taken into [0, 2)
 * (GLSL's mod(x, 2.0)), where the integral's floats are fine, and the ends back into [0, 2]
 * by a period. The width is at least 1e-4 (a magnified edge stays sharp) and at most a period,
 * where the mean is 0 whatever the width. */
static float filtered_wave(float x, float w)
{
    float p = x - 2.0f * floorf(0.5f * x);
    float h = 0.5f * clamp(w, 1e-4f, 2.0f);
    float a = p - h, b = p + h;
    float ia = wave_integral(a < 0.0f ? a + 2.0f : a);
    float ib = wave_integral(b > 2.0f ? b - 2.0f : b);
    return (ib - ia) / (2.0f * h);
}

static void checker(const sl_gbuffer_material *u, const sl_fragment_in *in, sl_gbuffer_texel *out,
                    sl_gbuffer_extra *extra)
{
    (void)extra;
    sl_gbuffer_varyings v = sl_gbuffer_varyings_of(in);
    vec2 uv = vec2(v.vTexCoord.x * u->uKdMapST.x + u->uKdMapST.z, v.vTexCoord.y * u->uKdMapST.y + u->uKdMapST.w);
    vec2 p = scale(uv, CELLS);
    vec2 w = fwidth(in, p);
    /* +1 where the cell's row and column have the same parity, -1 where not, filtered */
    float c = filtered_wave(p.x, w.x) * filtered_wave(p.y, w.y);
    float t = 0.5f - 0.5f * c;
    vec3 tone = mix(vec3(0.85f, 0.80f, 0.70f), vec3(0.10f, 0.12f, 0.16f), t);
    vec3 kd = mul(u->uKd, tone);
    if (u->uMaps & SL_GBUFFER_MAP_KD)
        kd = mul(kd, xyz(texture(in, &u->uKdMap, uv)));
    out->position = v.vWorldPos;
    out->normal = dot(v.vNormal, v.vNormal) > 1e-30f ? normalize(v.vNormal) : vec3(0, 0, 1);
    out->kd = kd;
    out->ks = u->uKs;
    out->alpha = u->uRoughness >= 0.0f ? -1.0f - u->uRoughness : u->uAlpha;
}

SL_GBUFFER_PROGRAM("checker", checker, SL_GBUFFER_DERIVATIVES);

/* softlight/glsl.h - GLSL's vocabulary in C11, so shaders can be ported line by line.
 *
 * Opt-in: no other public header includes it. A C shader source includes it to write
 * vec3, dot, normalize, dFdx, texture ... as GLSL does; the names are unprefixed, so it is
 * meant for shader sources, not for headers that others include. It is C11 only (_Generic,
 * compound literals): a C++ includer gets an error, and uses the sl_ API instead.
 *
 * Owns: GLSL's names for the vector and matrix types (vec2 is sl_vec2, ..., the same
 * types, types.h) and the GLSL built-ins the shaders use, including the fragment
 * built-ins (dFdx, dFdy, fwidth, discard, texture, textureLod, textureGrad,
 * texelFetch, textureSize) on top of program.h and texture.h. Everything is float32
 * and static inline, as in GLSL; double belongs to precomputation and references.
 *
 * C has no operator overloading, so arithmetic is spelled out:
 *     GLSL  a + b * c        C  add(a, mul(b, c))
 *     GLSL  v * 2.0          C  scale(v, 2.0f)
 * Constructors read like GLSL: vec3(x, y, z); splats are vec3s(s).
 * The overloaded built-ins (dot, length, normalize, mix, clamp, add, sub, mul,
 * scale, min/max as vmin/vmax, abs as vabs) dispatch on the first argument with
 * _Generic. Scalar float forms use the same names where GLSL does
 * (clamp(x, 0.0f, 1.0f), mix(a, b, t)); plain C math (sqrtf, powf) stays plain.
 *
 * Matrices are column-major like GLSL and OpenGL: m.c[col].x is row 0 of that
 * column, and a mat4 can be handed to glUniformMatrix4fv without transposing.
 *
 * Integer vectors: ivec2 only (texelFetch and textureSize take and return one).
 *
 * Lighting programs (softlight/lighting.h): a source that defines SL_GLSL_LIGHTING before
 * including this header also gets the lighting section at the end, lighting.frag's own names
 * for the toolbox (irradiance, env_lod, hammersley_point, point_light, specular_env_lights,
 * background, facing_normal, lobe_param, the sl_brdf_* / sl_ggx_* / sl_lobe_* BRDF terms,
 * sl_dir_to_uv, textureLod on the environment). The resources pass explicitly, as `in` does for
 * the derivatives: GLSL `irradiance(N)` is `irradiance(res, N)`.
 *
 * Does not: provide swizzles beyond .x/.y/.z/.w members and xyz(), or integer
 * vectors beyond ivec2. */
#ifndef SOFTLIGHT_GLSL_H
#define SOFTLIGHT_GLSL_H

#ifdef __cplusplus
#error "softlight/glsl.h is a C11 vocabulary (_Generic, compound literals); from C++ use the sl_ API of softlight/softlight.h"
#endif

#include <math.h>
#include <stdbool.h>

#include <softlight/program.h>
#include <softlight/texture.h>
#include <softlight/types.h>

typedef sl_vec2 vec2;
typedef sl_vec3 vec3;
typedef sl_vec4 vec4;
typedef sl_mat3 mat3; /* c[column] */
typedef sl_mat4 mat4; /* c[column] */
typedef sl_ivec2 ivec2;

#define SL_PI 3.14159265358979323846f

/* GLSL-style constructors. A function-like macro named like the type expands
 * only when followed by '(', so `vec3 v = vec3(1, 2, 3);` works. */
#define vec2(x, y) ((vec2){(float)(x), (float)(y)})
#define vec3(x, y, z) ((vec3){(float)(x), (float)(y), (float)(z)})
#define vec4(x, y, z, w) ((vec4){(float)(x), (float)(y), (float)(z), (float)(w)})
#define ivec2(x, y) ((ivec2){(int)(x), (int)(y)})
static inline vec2 vec2s(float s) { return (vec2){s, s}; }
static inline vec3 vec3s(float s) { return (vec3){s, s, s}; }
static inline vec4 vec4s(float s) { return (vec4){s, s, s, s}; }
static inline vec4 vec4_from3(vec3 v, float w) { return (vec4){v.x, v.y, v.z, w}; }
static inline vec3 xyz(vec4 v) { return (vec3){v.x, v.y, v.z}; }

/* ---- scalar helpers with GLSL names ---- */
static inline float clampf(float x, float lo, float hi) { return x < lo ? lo : (x > hi ? hi : x); }
static inline float mixf(float a, float b, float t) { return a + (b - a) * t; }
static inline float minf(float a, float b) { return a < b ? a : b; }
static inline float maxf(float a, float b) { return a > b ? a : b; }
static inline float radians(float deg) { return deg * (SL_PI / 180.0f); }
static inline float degrees(float rad) { return rad * (180.0f / SL_PI); }
static inline float smoothstep(float e0, float e1, float x)
{
    float t = clampf((x - e0) / (e1 - e0), 0.0f, 1.0f);
    return t * t * (3.0f - 2.0f * t);
}
static inline float fract(float x) { return x - floorf(x); }
static inline float sign(float x) { return x > 0.0f ? 1.0f : (x < 0.0f ? -1.0f : 0.0f); }
/* GLSL's pow, exp2, log2 are the C ones on floats. */

/* ---- vec2 ---- */
static inline vec2 add2(vec2 a, vec2 b) { return (vec2){a.x + b.x, a.y + b.y}; }
static inline vec2 sub2(vec2 a, vec2 b) { return (vec2){a.x - b.x, a.y - b.y}; }
static inline vec2 mul2(vec2 a, vec2 b) { return (vec2){a.x * b.x, a.y * b.y}; }
static inline vec2 scale2(vec2 a, float s) { return (vec2){a.x * s, a.y * s}; }
static inline float dot2(vec2 a, vec2 b) { return a.x * b.x + a.y * b.y; }
static inline float length2(vec2 a) { return sqrtf(dot2(a, a)); }
static inline vec2 normalize2(vec2 a) { return scale2(a, 1.0f / length2(a)); }
static inline vec2 mix2(vec2 a, vec2 b, float t) { return (vec2){mixf(a.x, b.x, t), mixf(a.y, b.y, t)}; }
static inline vec2 clamp2(vec2 a, float lo, float hi) { return (vec2){clampf(a.x, lo, hi), clampf(a.y, lo, hi)}; }
static inline vec2 vmin2(vec2 a, vec2 b) { return (vec2){minf(a.x, b.x), minf(a.y, b.y)}; }
static inline vec2 vmax2(vec2 a, vec2 b) { return (vec2){maxf(a.x, b.x), maxf(a.y, b.y)}; }
static inline vec2 vabs2(vec2 a) { return (vec2){fabsf(a.x), fabsf(a.y)}; }

/* ---- vec3 ---- */
static inline vec3 add3(vec3 a, vec3 b) { return (vec3){a.x + b.x, a.y + b.y, a.z + b.z}; }
static inline vec3 sub3(vec3 a, vec3 b) { return (vec3){a.x - b.x, a.y - b.y, a.z - b.z}; }
static inline vec3 mul3(vec3 a, vec3 b) { return (vec3){a.x * b.x, a.y * b.y, a.z * b.z}; }
static inline vec3 scale3(vec3 a, float s) { return (vec3){a.x * s, a.y * s, a.z * s}; }
static inline float dot3(vec3 a, vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline float length3(vec3 a) { return sqrtf(dot3(a, a)); }
static inline vec3 normalize3(vec3 a) { return scale3(a, 1.0f / length3(a)); }
static inline vec3 mix3(vec3 a, vec3 b, float t)
{
    return (vec3){mixf(a.x, b.x, t), mixf(a.y, b.y, t), mixf(a.z, b.z, t)};
}
static inline vec3 clamp3(vec3 a, float lo, float hi)
{
    return (vec3){clampf(a.x, lo, hi), clampf(a.y, lo, hi), clampf(a.z, lo, hi)};
}
static inline vec3 vmin3(vec3 a, vec3 b) { return (vec3){minf(a.x, b.x), minf(a.y, b.y), minf(a.z, b.z)}; }
static inline vec3 vmax3(vec3 a, vec3 b) { return (vec3){maxf(a.x, b.x), maxf(a.y, b.y), maxf(a.z, b.z)}; }
static inline vec3 vabs3(vec3 a) { return (vec3){fabsf(a.x), fabsf(a.y), fabsf(a.z)}; }
static inline vec3 cross(vec3 a, vec3 b)
{
    return (vec3){a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
/* GLSL reflect(I, N) = I - 2 dot(N, I) N, N unit length. */
static inline vec3 reflect(vec3 i, vec3 n) { return sub3(i, scale3(n, 2.0f * dot3(n, i))); }

/* ---- vec4 ---- */
static inline vec4 add4(vec4 a, vec4 b) { return (vec4){a.x + b.x, a.y + b.y, a.z + b.z, a.w + b.w}; }
static inline vec4 sub4(vec4 a, vec4 b) { return (vec4){a.x - b.x, a.y - b.y, a.z - b.z, a.w - b.w}; }
static inline vec4 mul4(vec4 a, vec4 b) { return (vec4){a.x * b.x, a.y * b.y, a.z * b.z, a.w * b.w}; }
static inline vec4 scale4(vec4 a, float s) { return (vec4){a.x * s, a.y * s, a.z * s, a.w * s}; }
static inline float dot4(vec4 a, vec4 b) { return a.x * b.x + a.y * b.y + a.z * b.z + a.w * b.w; }
static inline float length4(vec4 a) { return sqrtf(dot4(a, a)); }
static inline vec4 normalize4(vec4 a) { return scale4(a, 1.0f / length4(a)); }
static inline vec4 mix4(vec4 a, vec4 b, float t)
{
    return (vec4){mixf(a.x, b.x, t), mixf(a.y, b.y, t), mixf(a.z, b.z, t), mixf(a.w, b.w, t)};
}
static inline vec4 clamp4(vec4 a, float lo, float hi)
{
    return (vec4){clampf(a.x, lo, hi), clampf(a.y, lo, hi), clampf(a.z, lo, hi), clampf(a.w, lo, hi)};
}
static inline vec4 vmin4(vec4 a, vec4 b)
{
    return (vec4){minf(a.x, b.x), minf(a.y, b.y), minf(a.z, b.z), minf(a.w, b.w)};
}
static inline vec4 vmax4(vec4 a, vec4 b)
{
    return (vec4){maxf(a.x, b.x), maxf(a.y, b.y), maxf(a.z, b.z), maxf(a.w, b.w)};
}
static inline vec4 vabs4(vec4 a) { return (vec4){fabsf(a.x), fabsf(a.y), fabsf(a.z), fabsf(a.w)}; }

/* ---- GLSL's overloaded names ---- */
#define SL_GENERIC(a, f2, f3, f4) _Generic((a), vec2: f2, vec3: f3, vec4: f4)
#define add(a, b) SL_GENERIC(a, add2, add3, add4)(a, b)
#define sub(a, b) SL_GENERIC(a, sub2, sub3, sub4)(a, b)
#define mul(a, b) SL_GENERIC(a, mul2, mul3, mul4)(a, b)
#define scale(a, s) SL_GENERIC(a, scale2, scale3, scale4)(a, s)
#define dot(a, b) SL_GENERIC(a, dot2, dot3, dot4)(a, b)
#define length(a) SL_GENERIC(a, length2, length3, length4)(a)
#define normalize(a) SL_GENERIC(a, normalize2, normalize3, normalize4)(a)
#define vmin(a, b) SL_GENERIC(a, vmin2, vmin3, vmin4)(a, b)
#define vmax(a, b) SL_GENERIC(a, vmax2, vmax3, vmax4)(a, b)
#define vabs(a) SL_GENERIC(a, vabs2, vabs3, vabs4)(a)
#define mix(a, b, t) _Generic((a), float: mixf, vec2: mix2, vec3: mix3, vec4: mix4)(a, b, t)
#define clamp(a, lo, hi) _Generic((a), float: clampf, vec2: clamp2, vec3: clamp3, vec4: clamp4)(a, lo, hi)

/* ---- mat3 ---- */
static inline mat3 mat3_identity(void)
{
    return (mat3){{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
}
static inline vec3 mat3_mul_vec3(mat3 m, vec3 v)
{
    return add3(add3(scale3(m.c[0], v.x), scale3(m.c[1], v.y)), scale3(m.c[2], v.z));
}
static inline mat3 mat3_transpose(mat3 m)
{
    return (mat3){{{m.c[0].x, m.c[1].x, m.c[2].x},
                   {m.c[0].y, m.c[1].y, m.c[2].y},
                   {m.c[0].z, m.c[1].z, m.c[2].z}}};
}
static inline float mat3_determinant(mat3 m) { return dot3(m.c[0], cross(m.c[1], m.c[2])); }
/* Inverse by cofactors; a singular matrix gives all zeros (callers check the determinant). */
static inline mat3 mat3_inverse(mat3 m)
{
    float det = mat3_determinant(m);
    if (det == 0.0f)
        return (mat3){{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}};
    /* rows of the inverse are the cross products of the columns, over det */
    vec3 r0 = scale3(cross(m.c[1], m.c[2]), 1.0f / det);
    vec3 r1 = scale3(cross(m.c[2], m.c[0]), 1.0f / det);
    vec3 r2 = scale3(cross(m.c[0], m.c[1]), 1.0f / det);
    return mat3_transpose((mat3){{r0, r1, r2}});
}

/* ---- mat4 ---- */
static inline mat4 mat4_identity(void)
{
    return (mat4){{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}}};
}
static inline vec4 mat4_mul_vec4(mat4 m, vec4 v)
{
    return add4(add4(scale4(m.c[0], v.x), scale4(m.c[1], v.y)), add4(scale4(m.c[2], v.z), scale4(m.c[3], v.w)));
}
static inline mat4 mat4_mul(mat4 a, mat4 b)
{
    mat4 r;
    for (int i = 0; i < 4; i++)
        r.c[i] = mat4_mul_vec4(a, b.c[i]);
    return r;
}
static inline mat4 mat4_transpose(mat4 m)
{
    return (mat4){{{m.c[0].x, m.c[1].x, m.c[2].x, m.c[3].x},
                   {m.c[0].y, m.c[1].y, m.c[2].y, m.c[3].y},
                   {m.c[0].z, m.c[1].z, m.c[2].z, m.c[3].z},
                   {m.c[0].w, m.c[1].w, m.c[2].w, m.c[3].w}}};
}
/* The upper-left 3x3, e.g. for normal matrices: transpose(inverse(mat3(model))). */
static inline mat3 mat3_from_mat4(mat4 m) { return (mat3){{xyz(m.c[0]), xyz(m.c[1]), xyz(m.c[2])}}; }
static inline mat4 mat4_inverse(mat4 m) { return sl_mat4_inverse(m); } /* singular gives all zeros */
static inline mat4 mat4_translate(vec3 t)
{
    mat4 m = mat4_identity();
    m.c[3] = vec4(t.x, t.y, t.z, 1.0f);
    return m;
}
static inline mat4 mat4_scale(vec3 s)
{
    return (mat4){{{s.x, 0, 0, 0}, {0, s.y, 0, 0}, {0, 0, s.z, 0}, {0, 0, 0, 1}}};
}
/* Rotation by `angle` radians about the unit `axis`, right-handed. */
static inline mat4 mat4_rotate(vec3 axis, float angle) { return sl_mat4_rotate(axis, angle); }
/* gluLookAt: the view matrix of an eye at `eye` looking at `center`. */
static inline mat4 lookAt(vec3 eye, vec3 center, vec3 up) { return sl_mat4_look_at(eye, center, up); }
/* gluPerspective: fovy in radians; maps z in [-near, -far] to NDC [-1, 1]. */
static inline mat4 perspective(float fovy, float aspect, float znear, float zfar)
{
    return sl_mat4_perspective(fovy, aspect, znear, zfar);
}

#define transpose(m) _Generic((m), mat3: mat3_transpose, mat4: mat4_transpose)(m)
#define inverse(m) _Generic((m), mat3: mat3_inverse, mat4: mat4_inverse)(m)

/* ---- fragment built-ins (program.h) ----
 *
 * A C shader has no hidden state, so the fragment's sl_fragment_in is passed explicitly:
 * GLSL `dFdx(uv)` is `dFdx(in, uv)`, `discard;` is `{ discard(in); return; }` (discard marks
 * the fragment; the shader then returns, as GLSL's discard ends the invocation). The
 * derivatives need a program with `derivatives = true` (it runs in 2x2 quads), discard one
 * with `discards = true`; elsewhere the derivatives return 0 and discard does nothing.
 *
 * dFdx is dFdxFine, as in llvmpipe, which computes every form with the same per-row
 * difference: each pixel gets the difference of its own row of the quad (dFdy: of its own
 * column). The coarse forms are what GLSL defines them as, one value for the quad (row y even
 * for dFdxCoarse, column x even for dFdyCoarse). How a derivative of any value the shader
 * computes is found, what it costs and its limits: docs/shader-api.md "Quads". */
static inline void discard(const sl_fragment_in *in) { sl_discard(in); }

/* The float, vec2, vec3 and vec4 forms of one derivative kind: fn1 .. fn4. */
#define SL_DERIVATIVE_FORMS(fn, kind)                                                                             \
    static inline float fn##1(const sl_fragment_in *in, float v)                                                  \
    {                                                                                                             \
        float d;                                                                                                  \
        sl_quad_derivative(in, kind, &v, 1, &d);                                                                  \
        return d;                                                                                                 \
    }                                                                                                             \
    static inline vec2 fn##2(const sl_fragment_in *in, vec2 v)                                                   \
    {                                                                                                             \
        float a[2] = {v.x, v.y}, d[2];                                                                            \
        sl_quad_derivative(in, kind, a, 2, d);                                                                    \
        return (vec2){d[0], d[1]};                                                                                \
    }                                                                                                             \
    static inline vec3 fn##3(const sl_fragment_in *in, vec3 v)                                                    \
    {                                                                                                             \
        float a[3] = {v.x, v.y, v.z}, d[3];                                                                       \
        sl_quad_derivative(in, kind, a, 3, d);                                                                    \
        return (vec3){d[0], d[1], d[2]};                                                                          \
    }                                                                                                             \
    static inline vec4 fn##4(const sl_fragment_in *in, vec4 v)                                                    \
    {                                                                                                             \
        float a[4] = {v.x, v.y, v.z, v.w}, d[4];                                                                  \
        sl_quad_derivative(in, kind, a, 4, d);                                                                    \
        return (vec4){d[0], d[1], d[2], d[3]};                                                                    \
    }

SL_DERIVATIVE_FORMS(sl_dfdx_fine, SL_DFDX_FINE)
SL_DERIVATIVE_FORMS(sl_dfdy_fine, SL_DFDY_FINE)
SL_DERIVATIVE_FORMS(sl_dfdx_coarse, SL_DFDX_COARSE)
SL_DERIVATIVE_FORMS(sl_dfdy_coarse, SL_DFDY_COARSE)
SL_DERIVATIVE_FORMS(sl_fwidth_fine, SL_FWIDTH_FINE)
SL_DERIVATIVE_FORMS(sl_fwidth_coarse, SL_FWIDTH_COARSE)

#define SL_DERIVATIVE_GENERIC(in, v, fn) _Generic((v), float: fn##1, vec2: fn##2, vec3: fn##3, vec4: fn##4)(in, v)
#define dFdx(in, v) SL_DERIVATIVE_GENERIC(in, v, sl_dfdx_fine)
#define dFdy(in, v) SL_DERIVATIVE_GENERIC(in, v, sl_dfdy_fine)
#define dFdxFine(in, v) SL_DERIVATIVE_GENERIC(in, v, sl_dfdx_fine)
#define dFdyFine(in, v) SL_DERIVATIVE_GENERIC(in, v, sl_dfdy_fine)
#define dFdxCoarse(in, v) SL_DERIVATIVE_GENERIC(in, v, sl_dfdx_coarse)
#define dFdyCoarse(in, v) SL_DERIVATIVE_GENERIC(in, v, sl_dfdy_coarse)
#define fwidth(in, v) SL_DERIVATIVE_GENERIC(in, v, sl_fwidth_fine)
#define fwidthFine(in, v) SL_DERIVATIVE_GENERIC(in, v, sl_fwidth_fine)
#define fwidthCoarse(in, v) SL_DERIVATIVE_GENERIC(in, v, sl_fwidth_coarse)

/* For a quad form (sl_program.fragment_quad): v[l] is a value of lane l; the derivative lane
 * `lane` gets, with the same expression as the generic path (so the two give the same bits).
 * A multi-quad form takes the same differences on its quads' lanes 4 q .. 4 q + 3. */
static inline float sl_quad_dfdx(const float v[4], int lane) { return v[lane | 1] - v[lane & 2]; }
static inline float sl_quad_dfdy(const float v[4], int lane) { return v[lane | 2] - v[lane & 1]; }
static inline float sl_quad_dfdx_coarse(const float v[4]) { return v[1] - v[0]; }
static inline float sl_quad_dfdy_coarse(const float v[4]) { return v[2] - v[0]; }

/* ---- texture built-ins (texture.h) ---- */

/* GLSL texture(s, uv, bias): the implicit level, one per 2x2 quad, computed as llvmpipe computes
 * it from the coarse derivatives of uv (lane 1 - lane 0 in x, lane 2 - lane 0 in y); the
 * position stays per pixel. A call counts as one derivative call (one record of uv), so a
 * program that calls it needs `derivatives = true`; without it the level is that of zero
 * derivatives (the base level, magnified). */
static inline vec4 textureBias(const sl_fragment_in *in, const sl_sampler2D *s, vec2 uv, float bias)
{
    float v[2] = {uv.x, uv.y}, dx[2], dy[2];
    sl_quad_gradients(in, true, v, 2, dx, dy);
    float lambda = sl_texture_lambda_quad(s, (vec2){dx[0], dx[1]}, (vec2){dy[0], dy[1]}, bias);
    return sl_texture_sample(s, uv, lambda);
}
static inline vec4 texture(const sl_fragment_in *in, const sl_sampler2D *s, vec2 uv)
{
    return textureBias(in, s, uv, 0.0f);
}
/* textureLod on an sl_sampler2D (the library's environment lookup adds its own overload). */
#define textureLod(s, uv, lod)                                                                              \
    _Generic((s), sl_sampler2D *: sl_texture_lod, const sl_sampler2D *: sl_texture_lod)(s, uv, lod)
static inline vec4 textureGrad(const sl_sampler2D *s, vec2 uv, vec2 dPdx, vec2 dPdy)
{
    return sl_texture_grad(s, uv, dPdx, dPdy);
}
static inline vec4 texelFetch(const sl_sampler2D *s, ivec2 p, int lod) { return sl_texel_fetch(s, p, lod); }
static inline ivec2 textureSize(const sl_sampler2D *s, int lod) { return sl_texture_size(s, lod); }

#endif

/* ---- the lighting section (opt-in: #define SL_GLSL_LIGHTING before the include) ----
 * Outside the include guard, so a source that included this header before defining
 * SL_GLSL_LIGHTING gets the section by including it again. */
#if defined(SL_GLSL_LIGHTING) && !defined(SOFTLIGHT_GLSL_LIGHTING_SECTION)
#define SOFTLIGHT_GLSL_LIGHTING_SECTION

#include <softlight/lighting.h>

/* GLSL textureLod(uEnv, uv, lod): the environment's chain, with the resources in uEnv's place. */
#undef textureLod
#define textureLod(s, uv, lod)                                                                              \
    _Generic((s), sl_sampler2D *: sl_texture_lod, const sl_sampler2D *: sl_texture_lod,                     \
             sl_lighting_resources *: sl_lighting_texture_lod,                                              \
             const sl_lighting_resources *: sl_lighting_texture_lod)(s, uv, lod)
static inline vec2 sl_dir_to_uv(vec3 d) { return sl_lighting_dir_to_uv(d); }
static inline vec3 sl_uv_to_dir(vec2 uv) { return sl_lighting_uv_to_dir(uv); }

/* the BRDF, both sets (alpha: the lobe parameter, >= 0 Phong, <= -1 GGX) */
static inline float sl_brdf_D(float NdotH, float alpha) { return sl_lighting_brdf_D(NdotH, alpha); }
static inline float sl_brdf_G(float LdotH, int gterm) { return sl_lighting_brdf_G(LdotH, gterm); }
static inline vec3 sl_brdf_F(vec3 Ks, float LdotH) { return sl_lighting_brdf_F(Ks, LdotH); }
static inline float sl_ggx_a2(float alpha) { return sl_lighting_ggx_a2(alpha); }
static inline float sl_ggx_D(float NdotH, float a2) { return sl_lighting_ggx_D(NdotH, a2); }
static inline float sl_ggx_G(float NdotL, float NdotV, float a2) { return sl_lighting_ggx_G(NdotL, NdotV, a2); }
static inline bool sl_lobe_is_ggx(float alpha) { return alpha < 0.0f; }
static inline float sl_lobe_D(float NdotH, float alpha) { return sl_lighting_lobe_D(NdotH, alpha); }
static inline float sl_lobe_G(float LdotH, float NdotL, float NdotV, float alpha, int gterm)
{
    return sl_lighting_lobe_G(LdotH, NdotL, NdotV, alpha, gterm);
}

/* lighting.frag's functions, the resources first */
static inline float lobe_param(float a) { return sl_lighting_lobe_param(a); }
static inline vec3 facing_normal(vec3 N, vec3 V) { return sl_lighting_facing_normal(N, V); }
static inline vec2 hammersley_point(const sl_lighting_resources *res, int k)
{
    return sl_lighting_hammersley_point(res, k);
}
static inline vec3 irradiance(const sl_lighting_resources *res, vec3 N) { return sl_lighting_irradiance(res, N); }
static inline vec3 env_lod(const sl_lighting_resources *res, vec3 w, float lod)
{
    return sl_lighting_env_lod(res, w, lod);
}
static inline vec3 specular_env_lights(const sl_lighting_resources *res, vec3 N, vec3 V, vec3 Ks, float alpha)
{
    return sl_lighting_env_lights(res, N, V, Ks, alpha);
}
static inline vec3 point_light(const sl_lighting_resources *res, int i, vec3 P, vec3 N, vec3 V, vec3 Kd, vec3 Ks,
                               float alpha)
{
    return sl_lighting_point_light(res, i, P, N, V, Kd, Ks, alpha);
}
/* GLSL background(gl_FragCoord.xy) for the texel `in` */
static inline vec3 background(const sl_lighting_resources *res, const sl_lighting_texel_in *in)
{
    return sl_lighting_background(res, in->x, in->y);
}

#endif

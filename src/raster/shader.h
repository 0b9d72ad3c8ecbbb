/* shader.h - the GLSL fragment built-ins for C fragment shaders: dFdx, dFdy and fwidth
 * (fine and coarse) on float, vec2, vec3 and vec4, and discard; plus the per-lane
 * differences a program's quad form (sl_program.fragment_quad) takes its own with. A
 * multi-quad form (sl_program.fragment_quads, raster.h) takes the same differences on its
 * quads' lanes 4 q .. 4 q + 3 (lane 1 - lane 0, lane 2 - lane 0 for the coarse ones) and
 * marks discards in sl_fragment_quads.discarded instead of calling discard().
 *
 * A C shader has no hidden state, so the fragment's sl_fragment_in is passed
 * explicitly: GLSL `dFdx(uv)` is `dFdx(in, uv)`, `discard;` is
 * `{ discard(in); return; }` (discard marks the fragment; the shader then returns, as
 * GLSL's discard ends the invocation). The derivatives need a program with
 * `derivatives = true` (it runs in 2x2 quads), discard one with `discards = true`;
 * elsewhere the derivatives return 0 and discard does nothing.
 *
 * dFdx is dFdxFine, as in llvmpipe, which computes every form (fddx, fddx_fine,
 * fddx_coarse) with the same per-row difference: each pixel gets the difference of its
 * own row of the quad (dFdy: of its own column). The coarse forms here are what GLSL
 * defines them as, one value for the quad (row y even for dFdxCoarse, column x even for
 * dFdyCoarse). How a derivative of any value the shader computes is found (rounds to
 * a fixed point), what it costs and its limits: docs/shader-api.md "Quads".

 *
 * texture(in, s, uv), the implicit-level sample, is in shader_texture.h (kept apart:
 * texture.h's textureLod is also the environment's name in ibl.h). */
#ifndef SL_SHADER_H
#define SL_SHADER_H

#include "raster.h"

typedef enum {
    SL_DFDX_FINE,
    SL_DFDY_FINE,
    SL_DFDX_COARSE,
    SL_DFDY_COARSE,
    SL_FWIDTH_FINE,   /* |dFdxFine| + |dFdyFine| of one recorded value */
    SL_FWIDTH_COARSE, /* |dFdxCoarse| + |dFdyCoarse| */
} sl_derivative;

/* The derivative `kind` of the n (1..4) floats v, into d (quad.c). */
void sl_quad_derivative(const sl_fragment_in *in, sl_derivative kind, const float *v, int n, float *d);
/* Both derivatives of the n (1..4) floats v from one record: dx, dy (coarse or fine). */
void sl_quad_gradients(const sl_fragment_in *in, bool coarse, const float *v, int n, float *dx, float *dy);
/* Mark the fragment discarded: nothing of it is written (quad.c). */
void sl_discard(const sl_fragment_in *in);
static inline void discard(const sl_fragment_in *in) { sl_discard(in); }
/* Does a store outside the fragment's texel (an image store: the uniforms' planes) take effect
 * in this invocation? Not for a helper (as in GL), nor in a round of the generic quad rounds
 * before their fixed point, whose values may still change (quad.c): a shader that stores
 * guards each store with it and sets sl_program.stores. */
bool sl_fragment_stores(const sl_fragment_in *in);

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

/* For a quad form: v[l] is a value of lane l; the derivative lane `lane` gets, with
 * the same expression as the generic path (so the two give the same bits). */
static inline float sl_quad_dfdx(const float v[4], int lane) { return v[lane | 1] - v[lane & 2]; }
static inline float sl_quad_dfdy(const float v[4], int lane) { return v[lane | 2] - v[lane & 1]; }
static inline float sl_quad_dfdx_coarse(const float v[4]) { return v[1] - v[0]; }
static inline float sl_quad_dfdy_coarse(const float v[4]) { return v[2] - v[0]; }

#endif

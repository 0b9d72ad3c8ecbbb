/* shader_texture.h - GLSL's texture(s, uv[, bias]) for C fragment shaders: the sample with
 * the implicit level of detail, on top of shader.h's quads and texture.h's sampling.
 *
 * The level is computed as llvmpipe computes it: one lambda per 2x2 quad, from the coarse
 * derivatives of uv (lane 1 - lane 0 in x, lane 2 - lane 0 in y: llvmpipe's
 * lp_build_packed_ddx_ddy_twocoord), through sl_texture_lambda_quad; the position stays
 * per pixel. A call counts as one derivative call (one record of uv), so a program that calls
 * it needs `derivatives = true`; without it the level is that of zero derivatives (the
 * base level, magnified). Kept out of shader.h because texture.h's textureLod is also
 * ibl.h's name for the environment lookup: a file that needs both includes only one. */
#ifndef SL_SHADER_TEXTURE_H
#define SL_SHADER_TEXTURE_H

#include "shader.h"
#include "texture.h"

/* GLSL texture(s, uv, bias): the implicit level, one per quad (above). */
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

#endif

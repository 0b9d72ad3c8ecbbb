/* lighting_program.c - the lighting-program contract's library side (softlight/lighting.h): the
 * built-in shading as a program, and the toolbox any program calls, each a thin wrapper over the
 * port's own function (lighting.c) or the BRDF (brdf.h), so a program gets the built-in's bits.
 *
 * Does not: run programs over a G-buffer (lighting_pass.c), load them (src/app/lighting_load.c,
 * through program_load.c). */
#include "../ibl/texture_lod.h"
#include "lighting_internal.h"

/* ---- the built-in program ---- */

static sl_vec3 builtin_shade(const sl_lighting_frame_uniforms *f, const sl_lighting_resources *res,
                             const sl_lighting_texel_in *in)
{
    (void)f;
    return sl_lighting_builtin_texel(res->u, res->gb, in->x, in->y, res->task, res->trace);
}

static void builtin_shade_span(const sl_lighting_frame_uniforms *f, const sl_lighting_resources *res,
                               const sl_lighting_span *span, sl_vec3 *out)
{
    (void)f;
    sl_lighting_builtin_row(res->u, res->gb, span->x0, span->y, span->count, res->task, out);
}

static const sl_lighting_program builtin = {"built-in", builtin_shade, builtin_shade_span};

const sl_lighting_program *sl_lighting_builtin(void) { return &builtin; }

/* ---- the toolbox ---- */

sl_vec3 sl_lighting_background(const sl_lighting_resources *res, int x, int y)
{
    return sl_shade_background(res->u, vec2((float)x + 0.5f, (float)y + 0.5f));
}

sl_vec3 sl_lighting_texture_lod(const sl_lighting_resources *res, sl_vec2 uv, float lod)
{
    return textureLod(res->u->uEnv, uv, lod);
}

sl_vec3 sl_lighting_env_lod(const sl_lighting_resources *res, sl_vec3 w, float lod)
{
    return sl_shade_env_lod(res->u, w, lod);
}

sl_vec3 sl_lighting_irradiance(const sl_lighting_resources *res, sl_vec3 N)
{
    return res->u->uIrradiance ? sl_shade_irradiance(res->u, N) : vec3s(0.0f);
}

sl_vec2 sl_lighting_hammersley_point(const sl_lighting_resources *res, int k)
{
    int n = (int)res->u->uHammersley.N;
    return k >= 0 && k < n ? sl_shade_hammersley_point(res->u, k) : vec2(0.0f, 0.0f);
}

sl_vec3 sl_lighting_env_lights(const sl_lighting_resources *res, sl_vec3 N, sl_vec3 V, sl_vec3 Ks, float alpha)
{
    return sl_shade_env_lights(res->u, N, V, Ks, shade_lobe_param(alpha));
}

sl_vec3 sl_lighting_point_light(const sl_lighting_resources *res, int i, sl_vec3 P, sl_vec3 N, sl_vec3 V, sl_vec3 Kd,
                                sl_vec3 Ks, float alpha)
{
    if (i < 0 || i >= res->u->uLightCount)
        return vec3s(0.0f);
    return sl_shade_point_light(res->u, i, P, N, V, Kd, Ks, shade_lobe_param(alpha));
}

sl_vec2 sl_lighting_dir_to_uv(sl_vec3 d) { return sl_dir_to_uv(d); }
sl_vec3 sl_lighting_uv_to_dir(sl_vec2 uv) { return sl_uv_to_dir(uv); }
sl_vec3 sl_lighting_facing_normal(sl_vec3 N, sl_vec3 V) { return sl_shade_facing_normal(N, V); }
float sl_lighting_lobe_param(float alpha) { return shade_lobe_param(alpha); }

float sl_lighting_brdf_D(float NdotH, float alpha) { return sl_brdf_D(NdotH, alpha); }
float sl_lighting_brdf_G(float LdotH, int gterm) { return sl_brdf_G(LdotH, (sl_gterm)gterm); }
sl_vec3 sl_lighting_brdf_F(sl_vec3 Ks, float LdotH) { return sl_brdf_F(Ks, LdotH); }
float sl_lighting_ggx_a2(float alpha) { return sl_ggx_a2(alpha); }
float sl_lighting_ggx_D(float NdotH, float a2) { return sl_ggx_D(NdotH, a2); }
float sl_lighting_ggx_G(float NdotL, float NdotV, float a2) { return sl_ggx_G(NdotL, NdotV, a2); }
float sl_lighting_lobe_D(float NdotH, float alpha) { return sl_lobe_D(NdotH, alpha); }
float sl_lighting_lobe_G(float LdotH, float NdotL, float NdotV, float alpha, int gterm)
{
    return sl_lobe_G(LdotH, NdotL, NdotV, alpha, (sl_gterm)gterm);
}

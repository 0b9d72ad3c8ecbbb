/* normals.c - a lighting program for debugging the G-buffer: the shading normal (after
 * facing_normal, as the built-in shades with) as colour, N * 0.5 + 0.5, and mid grey where
 * nothing was drawn. The output is radiance: tone mapping still applies (use -e 0 -c 1 ... to
 * taste). */
#define SL_GLSL_LIGHTING
#include <softlight/glsl.h>

static vec3 normals_shade(const sl_lighting_frame_uniforms *u, const sl_lighting_resources *res,
                          const sl_lighting_texel_in *in)
{
    (void)res;
    const sl_gbuffer_texel *t = in->texel;
    if (t->depth >= 1.0f)
        return vec3s(0.5f);
    vec3 V = normalize(sub(u->eye, t->position));
    return add(scale(facing_normal(t->normal, V), 0.5f), vec3s(0.5f));
}

SL_LIGHTING_PROGRAM("normals", normals_shade, NULL);

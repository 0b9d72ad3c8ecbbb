/* toon.c - a lighting program: cel shading. The diffuse light (the environment's irradiance and
 * the point lights, Lambert) is quantised to three bands of the albedo, silhouettes are inked
 * black, and a hard highlight marks the brightest light's reflection. It has a span form, the
 * same function over a row, as a vectorizing program would. */
#define SL_GLSL_LIGHTING
#include <softlight/glsl.h>

static float luminance(vec3 c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

static vec3 toon_shade(const sl_lighting_frame_uniforms *u, const sl_lighting_resources *res,
                       const sl_lighting_texel_in *in)
{
    const sl_gbuffer_texel *t = in->texel;
    if (t->depth >= 1.0f)
        return scale(background(res, in), 0.5f);
    vec3 V = normalize(sub(u->eye, t->position));
    vec3 N = facing_normal(t->normal, V);
    if (dot(N, V) < 0.2f) /* the silhouette's ink */
        return vec3s(0.0f);
    float light = luminance(irradiance(res, mat3_mul_vec3(u->env_rotation, N))) * u->env_intensity / SL_PI;
    float highlight = 0.0f;
    for (int i = 0; i < u->light_count; i++) {
        vec3 toLight = sub(u->light_position[i], t->position);
        float d2 = maxf(dot(toLight, toLight), 1e-8f);
        vec3 L = scale(toLight, 1.0f / sqrtf(d2));
        float NdotL = maxf(dot(N, L), 0.0f);
        light += NdotL * luminance(u->light_color[i]) * u->light_intensity[i] / d2 / SL_PI;
        highlight = maxf(highlight, dot(N, normalize(add(L, V))));
    }
    float band = light > 0.6f ? 1.0f : light > 0.25f ? 0.6f : 0.3f;
    vec3 color = scale(t->kd, band);
    if (highlight > 0.98f)
        color = add(color, vec3s(0.8f));
    return add(color, in->extra.emissive);
}

static void toon_span(const sl_lighting_frame_uniforms *u, const sl_lighting_resources *res,
                      const sl_lighting_span *span, sl_vec3 *out)
{
    for (int i = 0; i < span->count; i++) {
        sl_gbuffer_extra none = {.occlusion = 1.0f};
        sl_lighting_texel_in in = {&span->texels[i], span->extra ? span->extra[i] : none, span->x0 + i, span->y};
        out[i] = toon_shade(u, res, &in);
    }
}

SL_LIGHTING_PROGRAM("toon", toon_shade, toon_span);

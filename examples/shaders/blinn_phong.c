/* blinn_phong.c - a lighting program: Lambert diffuse and Blinn-Phong highlights from the scene's
 * point lights, the environment's irradiance as the ambient term, the environment behind empty
 * pixels. Run it: softlight render scenes/bunny.json --lighting examples/shaders/blinn_phong.c */
#define SL_GLSL_LIGHTING
#include <softlight/glsl.h>

/* The Blinn-Phong exponent of a lobe: the Phong exponent itself, or GGX's equal-peak one. */
static float shininess(float alpha)
{
    if (sl_lobe_is_ggx(alpha))
        return 2.0f / sl_ggx_a2(alpha) - 2.0f;
    return alpha;
}

static vec3 blinn_phong(const sl_lighting_frame_uniforms *u, const sl_lighting_resources *res,
                        const sl_lighting_texel_in *in)
{
    const sl_gbuffer_texel *t = in->texel;
    if (t->depth >= 1.0f)
        return background(res, in);
    vec3 P = t->position;
    vec3 V = normalize(sub(u->eye, P));
    vec3 N = facing_normal(t->normal, V);
    float n = clamp(shininess(lobe_param(t->alpha)), 1.0f, 4096.0f);
    /* ambient: Lambert under the environment, E(N) Kd / pi */
    vec3 E = irradiance(res, mat3_mul_vec3(u->env_rotation, N));
    vec3 color = scale(mul(t->kd, E), u->env_intensity / SL_PI);
    color = scale(color, in->extra.occlusion);
    for (int i = 0; i < u->light_count; i++) {
        vec3 toLight = sub(u->light_position[i], P);
        float d2 = maxf(dot(toLight, toLight), 1e-8f);
        vec3 L = scale(toLight, 1.0f / sqrtf(d2));
        float NdotL = dot(N, L);
        if (NdotL <= 0.0f)
            continue;
        vec3 H = normalize(add(L, V));
        float spec = (n + 8.0f) / (8.0f * SL_PI) * powf(maxf(dot(N, H), 0.0f), n);
        vec3 f = add(scale(t->kd, 1.0f / SL_PI), scale(t->ks, spec));
        color = add(color, scale(mul(f, u->light_color[i]), u->light_intensity[i] / d2 * NdotL));
    }
    return add(color, in->extra.emissive);
}

SL_LIGHTING_PROGRAM("blinn-phong", blinn_phong, NULL);

#version 330 core
// blinn_phong.frag - the GLSL twin of blinn_phong.c: Lambert diffuse and Blinn-Phong highlights
// from the scene's point lights, the environment's irradiance as the ambient term, the
// environment behind empty pixels. Compiled after shaders/lighting.frag (its main renamed), so
// lighting.frag's uniforms (uEye, uLightPosition, ...) and functions (irradiance, background,
// facing_normal, lobe_param, ...) are in scope. Check it against its C twin:
//   softlight check scenes/bunny.json --lighting examples/shaders/blinn_phong.c \
//       --glsl examples/shaders/blinn_phong.frag

// The Blinn-Phong exponent of a lobe: the Phong exponent itself, or GGX's equal-peak one.
float shininess(float alpha)
{
    if (sl_lobe_is_ggx(alpha))
        return 2.0 / sl_ggx_a2(alpha) - 2.0;
    return alpha;
}

void main()
{
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    if (texelFetch(uDepth, pixel, 0).r >= 1.0) {
        fragColor = vec4(background(gl_FragCoord.xy), 1.0);
        return;
    }
    vec3 P = texelFetch(uPosition, pixel, 0).xyz;
    vec3 Kd = texelFetch(uKd, pixel, 0).rgb;
    vec4 KsAlpha = texelFetch(uKsAlpha, pixel, 0);
    vec3 V = normalize(uEye - P);
    vec3 N = facing_normal(texelFetch(uNormal, pixel, 0).xyz, V);
    float n = clamp(shininess(lobe_param(KsAlpha.a)), 1.0, 4096.0);
    vec4 extra = uHasExtra != 0 ? texelFetch(uExtra, pixel, 0) : vec4(1.0, 0.0, 0.0, 0.0);
    // ambient: Lambert under the environment, E(N) Kd / pi
    vec3 color = Kd * irradiance(uEnvRotation * N) * (uEnvIntensity / PI);
    color = color * extra.r;
    for (int i = 0; i < uLightCount; i++) {
        vec3 toLight = uLightPosition[i] - P;
        float d2 = max(dot(toLight, toLight), 1e-8);
        vec3 L = toLight * (1.0 / sqrt(d2));
        float NdotL = dot(N, L);
        if (NdotL <= 0.0)
            continue;
        vec3 H = normalize(L + V);
        float spec = (n + 8.0) / (8.0 * PI) * pow(max(dot(N, H), 0.0), n);
        vec3 f = Kd * (1.0 / PI) + KsAlpha.rgb * spec;
        color = color + f * uLightColor[i] * (uLightIntensity[i] / d2 * NdotL);
    }
    fragColor = vec4(color + extra.gba, 1.0);
}

#version 330 core
// toon.frag - the GLSL twin of toon.c: cel shading. The diffuse light (the environment's
// irradiance and the point lights, Lambert) is quantised to three bands of the albedo, silhouettes
// are inked black, and a hard highlight marks the brightest light's reflection. Compiled after
// shaders/lighting.frag (its main renamed). Its thresholds make C and GL disagree, by a whole band,
// on the few pixels whose light falls within float rounding of a threshold. Check it:
//   softlight check scenes/bunny.json --lighting examples/shaders/toon.c --glsl examples/shaders/toon.frag

float luminance(vec3 c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }

void main()
{
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    if (texelFetch(uDepth, pixel, 0).r >= 1.0) {
        fragColor = vec4(background(gl_FragCoord.xy) * 0.5, 1.0);
        return;
    }
    vec3 P = texelFetch(uPosition, pixel, 0).xyz;
    vec3 V = normalize(uEye - P);
    vec3 N = facing_normal(texelFetch(uNormal, pixel, 0).xyz, V);
    if (dot(N, V) < 0.2) { // the silhouette's ink
        fragColor = vec4(0.0, 0.0, 0.0, 1.0);
        return;
    }
    float light = luminance(irradiance(uEnvRotation * N)) * uEnvIntensity / PI;
    float highlight = 0.0;
    for (int i = 0; i < uLightCount; i++) {
        vec3 toLight = uLightPosition[i] - P;
        float d2 = max(dot(toLight, toLight), 1e-8);
        vec3 L = toLight * (1.0 / sqrt(d2));
        float NdotL = max(dot(N, L), 0.0);
        light += NdotL * luminance(uLightColor[i]) * uLightIntensity[i] / d2 / PI;
        highlight = max(highlight, dot(N, normalize(L + V)));
    }
    float band = light > 0.6 ? 1.0 : light > 0.25 ? 0.6 : 0.3;
    vec3 color = texelFetch(uKd, pixel, 0).rgb * band;
    if (highlight > 0.98)
        color = color + vec3(0.8);
    vec4 extra = uHasExtra != 0 ? texelFetch(uExtra, pixel, 0) : vec4(1.0, 0.0, 0.0, 0.0);
    fragColor = vec4(color + extra.gba, 1.0);
}

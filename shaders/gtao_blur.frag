#version 330 core
// gtao_blur.frag - ambient occlusion, each texel's value: the GLSL twin of src/occlusion/gtao.c
// (blurred), the mean over the 4 x 4 half-resolution block around the texel of the samples on
// its surface, multiplied into the extra target's occlusion (the material's map), and the
// texel's visibility cone (the same samples' bent normals' mean, normalised; the AO) into the
// cone target. BLUR_DEPTH and BLUR_NORMAL come as #defines from src/occlusion/gtao.h.

uniform sampler2D uPosition; // .w = 1 where covered
uniform sampler2D uNormal;
uniform sampler2D uExtra;    // occlusion, emission
uniform sampler2D uHalf;     // gtao.frag's samples: AO, unnormalised bent normal
uniform vec3 uEye, uForward;
uniform ivec2 uGrid;

layout(location = 0) out vec4 fragColor;
layout(location = 1) out vec4 fragCone; // bent normal, AO

// lighting.frag's facing_normal, with its constants
vec3 facing_normal(vec3 N, vec3 V)
{
    float len2 = dot(N, N);
    if (!(len2 > 1e-30))
        return V;
    N = N * (1.0 / sqrt(len2));
    float NdotV = dot(N, V);
    if (NdotV < 0.01)
        N = normalize(N + (0.01 - NdotV) * V);
    return N;
}

void main()
{
    ivec2 xy = ivec2(gl_FragCoord.xy);
    vec4 extra = texelFetch(uExtra, xy, 0);
    vec4 c = texelFetch(uPosition, xy, 0);
    vec3 cn = texelFetch(uNormal, xy, 0).xyz;
    if (c.w < 0.5) {
        fragColor = extra;
        fragCone = vec4(cn, 1.0);
        return;
    }
    float zc = dot(c.xyz - uEye, uForward);
    float sum = 0.0, n = 0.0;
    vec3 bent = vec3(0.0);
    ivec2 ij0 = xy / 2;
    for (int j = ij0.y - 1; j <= ij0.y + 2; j++)
        for (int i = ij0.x - 1; i <= ij0.x + 2; i++) {
            if (i < 0 || j < 0 || i >= uGrid.x || j >= uGrid.y)
                continue;
            vec4 q = texelFetch(uPosition, 2 * ivec2(i, j), 0);
            if (q.w < 0.5 || dot(texelFetch(uNormal, 2 * ivec2(i, j), 0).xyz, cn) < BLUR_NORMAL)
                continue;
            if (abs(dot(q.xyz - c.xyz, cn)) > BLUR_DEPTH * zc)
                continue;
            vec4 q_ao = texelFetch(uHalf, ivec2(i, j), 0);
            sum += q_ao.r;
            bent = bent + q_ao.gba;
            n += 1.0;
        }
    float ao = clamp(n > 0.0 ? sum / n : 1.0, 0.0, 1.0);
    float lb = length(bent);
    bent = lb > 1e-20 ? bent * (1.0 / lb) : facing_normal(cn, normalize(uEye - c.xyz));
    fragColor = vec4(extra.r * ao, extra.gba);
    fragCone = vec4(bent, ao);
}

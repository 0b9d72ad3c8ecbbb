#version 330 core
// gtao_blur.frag - ambient occlusion, each texel's value: the GLSL twin of src/occlusion/gtao.c
// (blurred), the mean over the 4 x 4 half-resolution block around the texel of the samples on
// its surface, multiplied into the extra target's occlusion (the material's map). BLUR_DEPTH and
// BLUR_NORMAL come as #defines from src/occlusion/gtao.h.

uniform sampler2D uPosition; // .w = 1 where covered
uniform sampler2D uNormal;
uniform sampler2D uExtra;    // occlusion, emission
uniform sampler2D uHalf;     // gtao.frag's samples
uniform vec3 uEye, uForward;
uniform ivec2 uGrid;

layout(location = 0) out vec4 fragColor;

void main()
{
    ivec2 xy = ivec2(gl_FragCoord.xy);
    vec4 extra = texelFetch(uExtra, xy, 0);
    vec4 c = texelFetch(uPosition, xy, 0);
    if (c.w < 0.5) {
        fragColor = extra;
        return;
    }
    vec3 cn = texelFetch(uNormal, xy, 0).xyz;
    float zc = dot(c.xyz - uEye, uForward);
    float sum = 0.0, n = 0.0;
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
            sum += texelFetch(uHalf, ivec2(i, j), 0).r;
            n += 1.0;
        }
    float ao = n > 0.0 ? sum / n : 1.0;
    fragColor = vec4(extra.r * clamp(ao, 0.0, 1.0), extra.gba);
}

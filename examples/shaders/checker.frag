// checker.frag - the GLSL twin of checker.c, line for line, for softlight-gl:
//   softlight-gl render scenes/textured.json --gbuffer-shader examples/shaders/checker.frag -o checker.png
// The material's diffuse colour as a checkerboard of two tones on its texture coordinates (CELLS
// cells per unit, after the kd map's uv transform), each pixel's value the pattern's mean over the
// pixel's footprint (its fwidth), so that cells smaller than a pixel fade to the two tones' mean.
// A kd map, where the material has one, multiplies the pattern. It runs behind softlight's
// shaders/gbuffer_textured.vert and sees the uniforms of shaders/gbuffer_textured.frag.
#version 330 core

in vec3 vWorldPos;
in vec3 vNormal;
in vec2 vTexCoord;

uniform vec3 uKd;
uniform vec3 uKs;
uniform float uAlpha;
uniform float uRoughness;
uniform sampler2D uKdMap;
uniform vec4 uKdMapST;
uniform int uMaps;

const int MAP_KD = 1; // SL_GBUFFER_MAP_KD
const float CELLS = 8.0;

layout(location = 0) out vec4 oPosition;
layout(location = 1) out vec4 oNormal;
layout(location = 2) out vec4 oKd;
layout(location = 3) out vec4 oKsAlpha;

// The integral from 0 of the square wave that is +1 on [0, 1) and -1 on [1, 2): a triangle wave
// of period 2, here on [0, 2].
float wave_integral(float x) { return 1.0 - abs(1.0 - x); }

// The square wave's mean over [x - w/2, x + w/2] (its box filter over the footprint).
float filtered_wave(float x, float w)
{
    float p = x - 2.0 * floor(0.5 * x);
    float h = 0.5 * clamp(w, 1e-4, 2.0);
    float a = p - h, b = p + h;
    float ia = wave_integral(a < 0.0 ? a + 2.0 : a);
    float ib = wave_integral(b > 2.0 ? b - 2.0 : b);
    return (ib - ia) / (2.0 * h);
}

void main()
{
    vec2 uv = vec2(vTexCoord.x * uKdMapST.x + uKdMapST.z, vTexCoord.y * uKdMapST.y + uKdMapST.w);
    vec2 p = uv * CELLS;
    vec2 w = fwidth(p);
    // +1 where the cell's row and column have the same parity, -1 where not, filtered
    float c = filtered_wave(p.x, w.x) * filtered_wave(p.y, w.y);
    float t = 0.5 - 0.5 * c;
    vec3 tone = mix(vec3(0.85, 0.80, 0.70), vec3(0.10, 0.12, 0.16), t);
    vec3 kd = uKd * tone;
    if ((uMaps & MAP_KD) != 0)
        kd = kd * texture(uKdMap, uv).rgb;
    oPosition = vec4(vWorldPos, 1.0);
    oNormal = vec4(dot(vNormal, vNormal) > 1e-30 ? normalize(vNormal) : vec3(0.0, 0.0, 1.0), 0.0);
    oKd = vec4(kd, 0.0);
    oKsAlpha = vec4(uKs, uRoughness >= 0.0 ? -1.0 - uRoughness : uAlpha);
}

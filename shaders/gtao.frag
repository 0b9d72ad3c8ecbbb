#version 330 core
// gtao.frag - ambient occlusion, the raw half-resolution samples: the GLSL twin of
// src/occlusion/gtao.c (texel_ao, horizon_cos, arc, acos_fast), line for line in its order.
// softlight-gl draws it over a (W + 1) / 2 x (H + 1) / 2 target after the G-buffer pass; fragment
// (i, j) is the sample of texel (2i, 2j): .r its AO, .gba its unnormalised bent normal. SLICES and STEPS come as #defines from
// src/occlusion/gtao.h (SL_GTAO_SLICES, SL_GTAO_STEPS), so both sides take them from one place.

uniform sampler2D uPosition; // .w = 1 where covered
uniform sampler2D uNormal;
uniform vec3 uEye, uForward, uRight, uUp;
uniform float uPixelsPerUnit; // screen radius (pixels) of one world unit at view depth 1
uniform vec2 uHalfSize;       // the image's centre, pixels
uniform float uRadius;
uniform float uMaxPixels;
uniform ivec2 uGrid;          // the half-resolution grid's size

layout(location = 0) out vec4 fragColor;

const float PI = 3.14159265358979;
const int PATTERN = 16;
const int bayer4[16] = int[16](0, 8, 2, 10, 12, 4, 14, 6, 3, 11, 1, 9, 15, 7, 13, 5);

float acos_fast(float x)
{
    float a = min(abs(x), 1.0);
    float r = sqrt(1.0 - a) * (1.5707288 + a * (-0.2121144 + a * (0.0742610 - 0.0187293 * a)));
    return x < 0.0 ? PI - r : r;
}

float arc(float c, float side, float n, float cos_n, float sin_n)
{
    float h = side * acos_fast(c);
    if (side * (h - n) >= 0.5 * PI) {
        h = n + side * 0.5 * PI;
        return 0.5 * (cos_n + h * sin_n);
    }
    float s = side * sqrt(max(0.0, 1.0 - c * c));
    float cos_2h = 2.0 * c * c - 1.0, sin_2h = 2.0 * s * c;
    return 0.25 * (-(cos_2h * cos_n + sin_2h * sin_n) + cos_n + 2.0 * h * sin_n);
}

void bent_arc(float c, float side, float n, float cos_n, float sin_n, out float along_v, out float along_dir)
{
    float h = side * acos_fast(c);
    float ch, sh;
    if (side * (h - n) >= 0.5 * PI) {
        ch = -side * sin_n;
        sh = side * cos_n;
    } else {
        ch = c;
        sh = side * sqrt(max(0.0, 1.0 - c * c));
    }
    float ch3 = ch * ch * ch, sh3 = sh * sh * sh;
    along_v = (cos_n * (1.0 - ch3) + sin_n * sh3) * (1.0 / 3.0);
    along_dir = cos_n * sh3 * (1.0 / 3.0) + sin_n * (2.0 / 3.0 - ch + ch3 * (1.0 / 3.0));
}

// The tangent plane (N, N.(P - eye)) of grid point (i, j): texel (2i, 2j); 0 where nothing was drawn.
vec4 plane(ivec2 ij)
{
    ivec2 t = 2 * ij;
    if (texelFetch(uPosition, t, 0).w < 0.5)
        return vec4(0.0);
    vec3 n = texelFetch(uNormal, t, 0).xyz;
    return vec4(n, dot(texelFetch(uPosition, t, 0).xyz - uEye, n));
}

float horizon_cos(ivec2 xy, vec3 P, vec3 V, vec2 d, float pixels, float shift)
{
    float best = -1.0;
    for (int s = 0; s < STEPS; s++) {
        float t = pixels * (float(s) + shift) / float(STEPS);
        vec2 p = vec2(xy) + 0.5 + d * t;
        ivec2 sij = ivec2(floor(0.5 * p));
        if ((2 * sij == xy) || any(lessThan(sij, ivec2(0))) || any(greaterThanEqual(sij, uGrid)))
            continue;
        vec4 q = plane(sij);
        vec3 ray = uForward + uRight * ((p.x - uHalfSize.x) / uPixelsPerUnit) + uUp * ((p.y - uHalfSize.y) / uPixelsPerUnit);
        float along = dot(ray, q.xyz);
        if (!(abs(along) > 1e-6))
            continue;
        float depth = q.w / along;
        if (!(depth > 0.0))
            continue;
        vec3 dd = uEye + ray * depth - P;
        float l2 = dot(dd, dd);
        if (l2 > uRadius * uRadius || l2 < 1e-20)
            continue;
        best = max(best, dot(dd, V) / sqrt(l2));
    }
    return best;
}

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

vec4 texel_ao(ivec2 xy, ivec2 ij)
{
    vec4 pos = texelFetch(uPosition, xy, 0);
    if (pos.w < 0.5)
        return vec4(1.0, texelFetch(uNormal, xy, 0).xyz);
    vec3 P = pos.xyz;
    vec3 V = normalize(uEye - P);
    vec3 N = facing_normal(texelFetch(uNormal, xy, 0).xyz, V);
    vec4 open = vec4(1.0, N);
    float depth = dot(P - uEye, uForward);
    if (!(depth > 0.0))
        return open;
    float pixels = min(uRadius * uPixelsPerUnit / depth, uMaxPixels);
    if (pixels < 1.0)
        return open;
    int k = bayer4[(ij.x & 3) + 4 * (ij.y & 3)];
    float shift = (float(bayer4[((ij.x + 2) & 3) + 4 * ((ij.y + 1) & 3)]) + 0.5) / float(PATTERN);
    vec3 b1 = normalize(uRight - V * dot(V, uRight));
    vec3 b2 = cross(V, b1);
    vec3 E = P - uEye;
    float xc = dot(E, uRight), yc = dot(E, uUp);
    float sum = 0.0;
    vec3 bent = vec3(0.0);
    for (int slice = 0; slice < SLICES; slice++) {
        float phi = PI * (float(slice) + (float(k) + 0.5) / float(PATTERN)) / float(SLICES);
        vec3 dir = b1 * cos(phi) + b2 * sin(phi);
        vec3 axis = cross(dir, V);
        float df = dot(dir, uForward);
        vec2 d = vec2(dot(dir, uRight) * depth - xc * df, dot(dir, uUp) * depth - yc * df);
        float sl = length(d);
        if (!(sl > 0.0))
            continue;
        d = d / sl;
        vec3 Np = N - axis * dot(N, axis);
        float lp = length(Np);
        if (lp < 1e-6)
            continue;
        float cos_n = dot(Np, V) / lp, sin_n = dot(Np, dir) / lp;
        float n = (sin_n < 0.0 ? -1.0 : 1.0) * acos_fast(cos_n);
        float c_pos = horizon_cos(xy, P, V, d, pixels, shift);
        float c_neg = horizon_cos(xy, P, V, -d, pixels, shift);
        sum += lp * (arc(c_pos, 1.0, n, cos_n, sin_n) + arc(c_neg, -1.0, n, cos_n, sin_n));
        float v_pos, d_pos, v_neg, d_neg;
        bent_arc(c_pos, 1.0, n, cos_n, sin_n, v_pos, d_pos);
        bent_arc(c_neg, -1.0, n, cos_n, sin_n, v_neg, d_neg);
        bent = bent + (V * (v_pos + v_neg) + dir * (d_pos + d_neg)) * lp;
    }
    return vec4(sum / float(SLICES), bent);
}

void main()
{
    ivec2 ij = ivec2(gl_FragCoord.xy);
    fragColor = texel_ao(2 * ij, ij);
}

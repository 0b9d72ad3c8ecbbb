#!/usr/bin/env bash
# public_headers.sh BUILD - the public headers (include/softlight) stand alone and stay out of the
# user's way: each compiles alone as C11 (gcc, and clang when present; -Wall -Wextra -Werror
# -pedantic-errors) and as C++17 (g++), in a translation unit that defines its own add, clamp,
# length and dot and its own vec3 type. softlight/glsl.h, the opt-in GLSL vocabulary, compiles
# in a C11 shader source, a lighting program and a G-buffer program (examples/shaders/checker.c),
# and refuses C++ with its own message.
set -euo pipefail
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail=0
flags=(-Wall -Wextra -Werror -pedantic-errors -Iinclude -c)

ccs=(gcc)
command -v clang >/dev/null && ccs+=(clang)
cxx=""
command -v g++ >/dev/null && cxx=g++

for h in include/softlight/*.h; do
  name=$(basename "$h")
  [ "$name" = glsl.h ] && continue
  src=$work/${name%.h}.c
  cat >"$src" <<C
#include <softlight/$name>
#include <softlight/$name> /* twice: include guards */

/* The user's own names, which no public header may take. */
typedef struct { double a, b, c; } vec3;
typedef vec3 (*vec3_fn)(vec3 v);
static int add(int a, int b) { return a + b; }
static double clamp(double x, double lo, double hi) { return x < lo ? lo : x > hi ? hi : x; }
static double dot(vec3 p, vec3 q) { return p.a * q.a + p.b * q.b + p.c * q.c; }
static double length(vec3 p) { return dot(p, p); }
static vec3 ident(vec3 v) { return v; }

int main(void)
{
    vec3 v = {1, 2, 3};
    vec3_fn fn = ident;
    return add(0, (int)clamp(length(fn(v)), 0, 0));
}
C
  for cc in "${ccs[@]}"; do
    if ! "$cc" -std=c11 "${flags[@]}" -o "$work/out.o" "$src" 2>"$work/err"; then
      echo "FAIL: $name as C11 with $cc:"; cat "$work/err"; fail=1
    fi
  done
  if [ -n "$cxx" ]; then
    if ! "$cxx" -std=c++17 -x c++ "${flags[@]}" -o "$work/out.o" "$src" 2>"$work/err"; then
      echo "FAIL: $name as C++17 with $cxx:"; cat "$work/err"; fail=1
    fi
  fi
done

# A C11 shader source that opts into the GLSL vocabulary and the fragment built-ins.
cat >"$work/shader.c" <<'C'
#include <softlight/glsl.h>

typedef struct {
    mat4 uViewProj;
    sl_sampler2D uTex;
} uniforms;

static void vert(const void *u, const sl_vertex_in *in, vec4 *clip, float *varyings)
{
    const uniforms *un = u;
    *clip = mat4_mul_vec4(un->uViewProj, vec4(in->position.x, in->position.y, in->position.z, 1.0f));
    varyings[0] = in->texcoord.x;
    varyings[1] = in->texcoord.y;
}

static void frag(const void *u, const sl_fragment_in *in, void *texel)
{
    const uniforms *un = u;
    vec2 uv = vec2(in->varyings[0], in->varyings[1]);
    vec4 c = texture(in, &un->uTex, uv);
    vec3 n = normalize(cross(vec3(1, 0, 0), vec3(0, 1, 0)));
    float w = fwidth(in, uv.x) + length(dFdy(in, uv)) + dot(n, n);
    if (clamp(c.w, 0.0f, 1.0f) < 0.5f) {
        discard(in);
        return;
    }
    vec3 rgb = mix(xyz(c), xyz(textureLod(&un->uTex, uv, 0.0f)), 0.5f);
    *(vec4 *)texel = vec4_from3(scale(rgb, w), 1.0f);
}

const sl_program shader_program = {
    .vertex = vert, .fragment = frag, .varying_count = 2, .derivatives = true, .discards = true};
mat4 shader_camera(void) { return mul4(vec4s(1), vec4s(2)).x > 0 ? lookAt(vec3s(1), vec3s(0), vec3(0, 0, 1)) : mat4_identity(); }
C
for cc in "${ccs[@]}"; do
  if ! "$cc" -std=c11 "${flags[@]}" -o "$work/out.o" "$work/shader.c" 2>"$work/err"; then
    echo "FAIL: a C11 shader source with softlight/glsl.h, $cc:"; cat "$work/err"; fail=1
  fi
done
# A C11 lighting program with the GLSL vocabulary's lighting section (softlight/lighting.h).
cat >"$work/lighting.c" <<'C'
#define SL_GLSL_LIGHTING
#include <softlight/glsl.h>
#include <softlight/softlight.h>

static vec3 shade(const sl_lighting_frame_uniforms *u, const sl_lighting_resources *res, const sl_lighting_texel_in *in)
{
    const sl_gbuffer_texel *t = in->texel;
    if (t->depth >= 1.0f)
        return add(background(res, in), textureLod(res, sl_dir_to_uv(vec3(0, 0, 1)), 0.0f));
    vec3 V = normalize(sub(u->eye, t->position));
    vec3 N = facing_normal(t->normal, V);
    float alpha = lobe_param(t->alpha);
    vec3 c = add(irradiance(res, N), env_lod(res, N, 1.0f));
    c = add(c, specular_env_lights(res, N, V, t->ks, alpha));
    for (int i = 0; i < u->light_count; i++)
        c = add(c, point_light(res, i, t->position, N, V, t->kd, t->ks, alpha));
    vec2 xi = hammersley_point(res, 0);
    float d = sl_lobe_D(dot(N, V), alpha) * sl_lobe_G(0.5f, 0.5f, 0.5f, alpha, u->gterm) + xi.x;
    d += sl_brdf_D(0.5f, 10.0f) * sl_brdf_G(0.5f, 1) + sl_ggx_D(0.5f, sl_ggx_a2(-1.5f)) + sl_ggx_G(0.5f, 0.5f, 0.1f);
    return add(scale(c, d), sl_brdf_F(t->ks, 0.5f));
}
static void span(const sl_lighting_frame_uniforms *u, const sl_lighting_resources *res, const sl_lighting_span *s, vec3 *out)
{
    for (int i = 0; i < s->count; i++) {
        sl_lighting_texel_in in = {&s->texels[i], {1.0f, {0, 0, 0}, 0.0f}, s->x0 + i, s->y};
        out[i] = shade(u, res, &in);
    }
}
SL_LIGHTING_PROGRAM("test", shade, span);
C
for cc in "${ccs[@]}"; do
  if ! "$cc" -std=c11 "${flags[@]}" -fPIC -o "$work/out.o" "$work/lighting.c" 2>"$work/err"; then
    echo "FAIL: a C11 lighting program with SL_GLSL_LIGHTING, $cc:"; cat "$work/err"; fail=1
  fi
done
# A C11 G-buffer program with the GLSL vocabulary (softlight/gbuffer_program.h): the shipped example.
for cc in "${ccs[@]}"; do
  if ! "$cc" -std=c11 "${flags[@]}" -fPIC -o "$work/out.o" examples/shaders/checker.c 2>"$work/err"; then
    echo "FAIL: examples/shaders/checker.c, a C11 G-buffer program, $cc:"; cat "$work/err"; fail=1
  fi
done
if [ -n "$cxx" ]; then
  echo '#include <softlight/glsl.h>' >"$work/glsl.cc"
  if "$cxx" -std=c++17 -Iinclude -c -o "$work/out.o" "$work/glsl.cc" 2>"$work/err" ||
     ! grep -q "C11 vocabulary" "$work/err"; then
    echo "FAIL: softlight/glsl.h in C++ should stop with its own message:"; cat "$work/err"; fail=1
  fi
fi
exit $fail

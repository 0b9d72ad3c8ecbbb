/* test_math.c - glsl.h and glsl.c against values worked out by hand.
 *
 * Exact checks where the float arithmetic is exact (small integers, powers of two);
 * tolerances where a sqrt, a trig function or an inverse rounds, sized to a few ulps of
 * the magnitudes involved. */
#include "testutil.h"

#include <math.h>
#include <stdio.h>

#include <softlight/glsl.h>

#define assert_vec3(v, ex, ey, ez, tol) \
    do {                                \
        vec3 v_ = (v);                  \
        assert_near(v_.x, ex, tol);     \
        assert_near(v_.y, ey, tol);     \
        assert_near(v_.z, ez, tol);     \
    } while (0)
#define assert_vec4(v, ex, ey, ez, ew, tol) \
    do {                                    \
        vec4 v4_ = (v);                     \
        assert_near(v4_.x, ex, tol);        \
        assert_near(v4_.y, ey, tol);        \
        assert_near(v4_.z, ez, tol);        \
        assert_near(v4_.w, ew, tol);        \
    } while (0)

/* Largest |a(i,j) - b(i,j)| over the 16 entries. */
static double mat4_max_diff(mat4 a, mat4 b)
{
    double worst = 0.0;
    for (int c = 0; c < 4; c++) {
        const float *pa = &a.c[c].x, *pb = &b.c[c].x;
        for (int r = 0; r < 4; r++)
            worst = fmax(worst, fabs((double)pa[r] - (double)pb[r]));
    }
    return worst;
}

static double mat3_max_diff(mat3 a, mat3 b)
{
    double worst = 0.0;
    for (int c = 0; c < 3; c++) {
        const float *pa = &a.c[c].x, *pb = &b.c[c].x;
        for (int r = 0; r < 3; r++)
            worst = fmax(worst, fabs((double)pa[r] - (double)pb[r]));
    }
    return worst;
}

static mat3 mat3_mul(mat3 a, mat3 b)
{
    return (mat3){{mat3_mul_vec3(a, b.c[0]), mat3_mul_vec3(a, b.c[1]), mat3_mul_vec3(a, b.c[2])}};
}

static void test_constructors(void **state)
{
    (void)state;
    vec2 a = vec2(1, 2);
    vec3 b = vec3(1, 2, 3);
    vec4 c = vec4(1, 2, 3, 4);
    assert_true(a.x == 1.0f && a.y == 2.0f);
    assert_true(b.x == 1.0f && b.y == 2.0f && b.z == 3.0f);
    assert_true(c.x == 1.0f && c.y == 2.0f && c.z == 3.0f && c.w == 4.0f);
    vec4 d = vec4_from3(b, 7.0f);
    assert_true(d.x == 1.0f && d.y == 2.0f && d.z == 3.0f && d.w == 7.0f);
    vec3 e = xyz(c);
    assert_true(e.x == 1.0f && e.y == 2.0f && e.z == 3.0f);
    assert_true(vec2s(5).x == 5.0f && vec2s(5).y == 5.0f);
    assert_true(vec3s(-2).x == -2.0f && vec3s(-2).z == -2.0f);
    assert_true(vec4s(0.5f).w == 0.5f);
}

static void test_scalar_helpers(void **state)
{
    (void)state;
    assert_true(clampf(-1.0f, 0.0f, 1.0f) == 0.0f);
    assert_true(clampf(2.0f, 0.0f, 1.0f) == 1.0f);
    assert_true(clampf(0.25f, 0.0f, 1.0f) == 0.25f);
    assert_true(clamp(0.75f, 0.0f, 0.5f) == 0.5f); /* the _Generic float form */
    assert_true(mixf(2.0f, 6.0f, 0.25f) == 3.0f);
    assert_true(mix(2.0f, 6.0f, 1.0f) == 6.0f);
    assert_true(minf(3.0f, -1.0f) == -1.0f && maxf(3.0f, -1.0f) == 3.0f);
    assert_near(radians(180.0f), 3.14159265358979, 1e-6);
    assert_near(degrees(SL_PI / 2.0f), 90.0, 1e-5);
    /* smoothstep: t^2 (3 - 2t); t = 0.25 -> 0.0625 * 2.5 = 0.15625 exactly */
    assert_true(smoothstep(0.0f, 1.0f, 0.25f) == 0.15625f);
    assert_true(smoothstep(0.0f, 1.0f, 0.5f) == 0.5f);
    assert_true(smoothstep(2.0f, 4.0f, 3.0f) == 0.5f);
    assert_true(smoothstep(2.0f, 4.0f, 1.0f) == 0.0f);
    assert_true(smoothstep(2.0f, 4.0f, 9.0f) == 1.0f);
    assert_true(fract(2.75f) == 0.75f);
    assert_true(fract(-0.25f) == 0.75f); /* GLSL: x - floor(x) */
    assert_true(sign(-3.0f) == -1.0f && sign(0.0f) == 0.0f && sign(2.0f) == 1.0f);
}

static void test_vector_arithmetic(void **state)
{
    (void)state;
    vec2 a2 = add(vec2(1, 2), vec2(3, -5)), s2 = sub(vec2(1, 2), vec2(3, -5));
    assert_true(a2.x == 4.0f && a2.y == -3.0f && s2.x == -2.0f && s2.y == 7.0f);
    vec2 m2 = mul(vec2(2, 3), vec2(4, -1)), k2 = scale(vec2(2, 3), 0.5f);
    assert_true(m2.x == 8.0f && m2.y == -3.0f && k2.x == 1.0f && k2.y == 1.5f);
    assert_vec3(add(vec3(1, 2, 3), vec3(4, 5, 6)), 5, 7, 9, 0);
    assert_vec3(sub(vec3(1, 2, 3), vec3(4, 5, 6)), -3, -3, -3, 0);
    assert_vec3(mul(vec3(1, 2, 3), vec3(4, 5, 6)), 4, 10, 18, 0);
    assert_vec3(scale(vec3(1, 2, 3), -2.0f), -2, -4, -6, 0);
    assert_vec4(add(vec4(1, 2, 3, 4), vec4(1, 1, 1, 1)), 2, 3, 4, 5, 0);
    assert_vec4(sub(vec4(1, 2, 3, 4), vec4(1, 1, 1, 1)), 0, 1, 2, 3, 0);
    assert_vec4(mul(vec4(1, 2, 3, 4), vec4(2, 2, 2, 0.5f)), 2, 4, 6, 2, 0);
    assert_vec4(scale(vec4(1, 2, 3, 4), 0.25f), 0.25, 0.5, 0.75, 1, 0);
}

static void test_dot_length_normalize(void **state)
{
    (void)state;
    assert_true(dot(vec2(1, 2), vec2(3, 4)) == 11.0f);
    assert_true(dot(vec3(1, 2, 3), vec3(4, -5, 6)) == 12.0f);
    assert_true(dot(vec4(1, 2, 3, 4), vec4(1, 1, 1, 1)) == 10.0f);
    assert_true(length(vec2(3, 4)) == 5.0f);
    assert_true(length(vec3(2, 3, 6)) == 7.0f);
    assert_true(length(vec4(1, 1, 1, 1)) == 2.0f);
    vec2 n2 = normalize(vec2(3, 4));
    assert_near(n2.x, 0.6, 1e-7);
    assert_near(n2.y, 0.8, 1e-7);
    assert_vec3(normalize(vec3(0, 3, 4)), 0, 0.6, 0.8, 1e-7);
    assert_vec3(normalize(vec3(2, 3, 6)), 2.0 / 7, 3.0 / 7, 6.0 / 7, 1e-7);
    assert_vec4(normalize(vec4(1, 1, 1, 1)), 0.5, 0.5, 0.5, 0.5, 1e-7);
    /* a long vector stays unit length to float precision */
    assert_near(length(normalize(vec3(1e3f, -2e3f, 5e2f))), 1.0, 1e-6);
}

static void test_cross(void **state)
{
    (void)state;
    assert_vec3(cross(vec3(1, 0, 0), vec3(0, 1, 0)), 0, 0, 1, 0); /* right-handed: x cross y = z */
    assert_vec3(cross(vec3(0, 1, 0), vec3(0, 0, 1)), 1, 0, 0, 0);
    assert_vec3(cross(vec3(0, 0, 1), vec3(1, 0, 0)), 0, 1, 0, 0);
    /* (2*6 - 3*5, 3*4 - 1*6, 1*5 - 2*4) */
    vec3 a = vec3(1, 2, 3), b = vec3(4, 5, 6);
    assert_vec3(cross(a, b), -3, 6, -3, 0);
    assert_vec3(cross(b, a), 3, -6, 3, 0);
    assert_true(dot(cross(a, b), a) == 0.0f && dot(cross(a, b), b) == 0.0f);
    assert_vec3(cross(a, a), 0, 0, 0, 0);
}

static void test_reflect(void **state)
{
    (void)state;
    /* I - 2 (N.I) N: a ray going down-right bounces up-right off a floor */
    assert_vec3(reflect(vec3(1, -1, 0), vec3(0, 1, 0)), 1, 1, 0, 0);
    assert_vec3(reflect(vec3(0, 0, -2), vec3(0, 0, 1)), 0, 0, 2, 0);
    /* grazing: unchanged */
    assert_vec3(reflect(vec3(1, 0, 0), vec3(0, 0, 1)), 1, 0, 0, 0);
    /* a tilted normal, worked out: N = (1,1,0)/sqrt2, I = (-1,0,0): N.I = -1/sqrt2, R = I + sqrt2 N = (0,1,0) */
    float h = sqrtf(0.5f);
    assert_vec3(reflect(vec3(-1, 0, 0), vec3(h, h, 0)), 0, 1, 0, 1e-7);
    vec3 i = normalize(vec3(0.3f, -0.7f, 0.2f)), n = normalize(vec3(-0.1f, 0.9f, 0.4f));
    assert_near(length(reflect(i, n)), 1.0, 1e-6);
    assert_near(dot(reflect(i, n), n), -dot(i, n), 1e-6);
}

static void test_mix_clamp_minmax(void **state)
{
    (void)state;
    vec2 m2 = mix(vec2(0, 10), vec2(4, 20), 0.5f);
    assert_true(m2.x == 2.0f && m2.y == 15.0f);
    assert_vec3(mix(vec3(0, 10, -2), vec3(4, 20, 2), 0.25f), 1, 12.5, -1, 0);
    assert_vec4(mix(vec4(0, 0, 0, 0), vec4(8, 4, 2, 1), 0.75f), 6, 3, 1.5, 0.75, 0);
    vec2 c2 = clamp(vec2(-1, 3), 0.0f, 1.0f);
    assert_true(c2.x == 0.0f && c2.y == 1.0f);
    assert_vec3(clamp(vec3(-1, 0.5f, 2), 0.0f, 1.0f), 0, 0.5, 1, 0);
    assert_vec4(clamp(vec4(-1, 0.5f, 2, 1), 0.0f, 1.0f), 0, 0.5, 1, 1, 0);
    assert_vec3(vmin(vec3(1, 5, -3), vec3(2, 4, -4)), 1, 4, -4, 0);
    assert_vec3(vmax(vec3(1, 5, -3), vec3(2, 4, -4)), 2, 5, -3, 0);
    vec2 mn2 = vmin(vec2(1, 5), vec2(2, 4)), mx2 = vmax(vec2(1, 5), vec2(2, 4));
    assert_true(mn2.x == 1.0f && mn2.y == 4.0f && mx2.x == 2.0f && mx2.y == 5.0f);
    assert_vec4(vmin(vec4(1, 5, 0, 9), vec4(2, 4, 0, -9)), 1, 4, 0, -9, 0);
    assert_vec4(vmax(vec4(1, 5, 0, 9), vec4(2, 4, 0, -9)), 2, 5, 0, 9, 0);
    vec2 ab2 = vabs(vec2(-1, 2));
    assert_true(ab2.x == 1.0f && ab2.y == 2.0f);
    assert_vec3(vabs(vec3(-1, 2, -0.5f)), 1, 2, 0.5, 0);
    assert_vec4(vabs(vec4(-1, 2, -0.5f, -8)), 1, 2, 0.5, 8, 0);
}

/* M with rows [1 2 3; 0 1 4; 5 6 0]: det 1, inverse rows [-24 18 5; 20 -15 -4; -5 4 1] (by cofactors). */
static mat3 unimodular3(void)
{
    return (mat3){{{1, 0, 5}, {2, 1, 6}, {3, 4, 0}}}; /* columns */
}

static void test_mat3(void **state)
{
    (void)state;
    mat3 m = unimodular3();
    assert_vec3(mat3_mul_vec3(mat3_identity(), vec3(1, 2, 3)), 1, 2, 3, 0);
    assert_vec3(mat3_mul_vec3(m, vec3(1, 1, 1)), 6, 5, 11, 0); /* row sums */
    assert_vec3(mat3_mul_vec3(m, vec3(1, 0, 0)), 1, 0, 5, 0);  /* first column */
    assert_true(mat3_determinant(m) == 1.0f);
    assert_true(mat3_determinant((mat3){{{2, 0, 0}, {0, 3, 0}, {0, 0, 4}}}) == 24.0f);
    mat3 t = transpose(m);
    assert_vec3(t.c[0], 1, 2, 3, 0); /* the first row of m */
    assert_vec3(t.c[2], 5, 6, 0, 0);
    mat3 inv = inverse(m);
    mat3 expected = {{{-24, 20, -5}, {18, -15, 4}, {5, -4, 1}}}; /* columns of the hand inverse */
    assert_near(mat3_max_diff(inv, expected), 0, 0);
    assert_near(mat3_max_diff(mat3_mul(m, inv), mat3_identity()), 0, 1e-5);
    /* a rotation-and-scale: inverse times original is the identity */
    mat3 r = mat3_from_mat4(mat4_mul(mat4_rotate(vec3(1, 2, 3), 0.7f), mat4_scale(vec3(2, 0.5f, 3))));
    assert_near(mat3_max_diff(mat3_mul(r, inverse(r)), mat3_identity()), 0, 1e-5);
    assert_near(mat3_max_diff(mat3_mul(inverse(r), r), mat3_identity()), 0, 1e-5);
    /* singular: third column = first + second */
    mat3 s = {{{1, 2, 3}, {4, 5, 6}, {5, 7, 9}}};
    assert_true(mat3_determinant(s) == 0.0f);
    assert_near(mat3_max_diff(inverse(s), (mat3){{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}}), 0, 0);
}

static void test_mat4_basics(void **state)
{
    (void)state;
    mat4 t = mat4_translate(vec3(1, 2, 3)), s = mat4_scale(vec3(2, 2, 2));
    /* translate * scale applied to the point (1,1,1): scale first -> (2,2,2), then +(1,2,3) */
    assert_vec4(mat4_mul_vec4(mat4_mul(t, s), vec4(1, 1, 1, 1)), 3, 4, 5, 1, 0);
    assert_vec4(mat4_mul_vec4(mat4_mul(s, t), vec4(1, 1, 1, 1)), 4, 6, 8, 1, 0);
    /* directions (w = 0) ignore translation */
    assert_vec4(mat4_mul_vec4(t, vec4(1, 0, 0, 0)), 1, 0, 0, 0, 0);
    assert_near(mat4_max_diff(mat4_mul(mat4_identity(), t), t), 0, 0);
    mat4 a = {{{1, 2, 3, 4}, {5, 6, 7, 8}, {9, 10, 11, 12}, {13, 14, 15, 16}}};
    mat4 at = transpose(a);
    assert_vec4(at.c[0], 1, 5, 9, 13, 0); /* row 0 of a */
    assert_vec4(at.c[3], 4, 8, 12, 16, 0);
    assert_near(mat4_max_diff(transpose(at), a), 0, 0);
    mat3 upper = mat3_from_mat4(a);
    assert_vec3(upper.c[0], 1, 2, 3, 0);
    assert_vec3(upper.c[2], 9, 10, 11, 0);
}

static void test_mat4_inverse(void **state)
{
    (void)state;
    /* exact inverses worked out by hand */
    assert_near(mat4_max_diff(inverse(mat4_translate(vec3(1, -2, 3))), mat4_translate(vec3(-1, 2, -3))), 0, 0);
    assert_near(mat4_max_diff(inverse(mat4_scale(vec3(2, 4, 8))), mat4_scale(vec3(0.5f, 0.25f, 0.125f))), 0, 0);
    /* A * inverse(A) = I for several kinds of matrix */
    mat4 cases[] = {
        mat4_mul(mat4_translate(vec3(3, -1, 2)),
                 mat4_mul(mat4_rotate(vec3(0, 1, 1), 1.1f), mat4_scale(vec3(2, 3, 0.5f)))),
        lookAt(vec3(3, 4, 5), vec3(0, 0, 0), vec3(0, 0, 1)),
        perspective(radians(60.0f), 1.5f, 0.1f, 100.0f),
        {{{4, 1, 0, 2}, {1, 5, 1, 0}, {0, 2, 6, 1}, {1, 0, 1, 3}}}, /* diagonally dominant, not symmetric */
        {{{0, 1, 0, 0}, {0, 0, 1, 0}, {1, 0, 0, 0}, {0, 0, 0, 1}}}, /* a permutation: needs no pivot luck */
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        mat4 inv = inverse(cases[i]);
        double left = mat4_max_diff(mat4_mul(cases[i], inv), mat4_identity());
        double right = mat4_max_diff(mat4_mul(inv, cases[i]), mat4_identity());
        if (left > 1e-5 || right > 1e-5)
            print_error("case %zu: |A inv(A) - I| = %.3g, |inv(A) A - I| = %.3g\n", i, left, right);
        assert_true(left <= 1e-5 && right <= 1e-5);
    }
    /* singular: two equal columns -> all zeros */
    mat4 s = {{{1, 2, 3, 4}, {1, 2, 3, 4}, {0, 1, 0, 0}, {0, 0, 0, 1}}};
    assert_near(mat4_max_diff(inverse(s), (mat4){{{0}}}), 0, 0);
}

static void test_rotate(void **state)
{
    (void)state;
    mat4 rz = mat4_rotate(vec3(0, 0, 1), radians(90.0f));
    assert_vec4(mat4_mul_vec4(rz, vec4(1, 0, 0, 0)), 0, 1, 0, 0, 1e-7); /* X -> Y */
    assert_vec4(mat4_mul_vec4(rz, vec4(0, 1, 0, 0)), -1, 0, 0, 0, 1e-7); /* Y -> -X */
    assert_vec4(mat4_mul_vec4(rz, vec4(0, 0, 1, 1)), 0, 0, 1, 1, 1e-7);  /* the axis stays */
    assert_vec4(mat4_mul_vec4(mat4_rotate(vec3(1, 0, 0), radians(90.0f)), vec4(0, 1, 0, 0)), 0, 0, 1, 0, 1e-7);
    assert_vec4(mat4_mul_vec4(mat4_rotate(vec3(0, 1, 0), radians(90.0f)), vec4(0, 0, 1, 0)), 1, 0, 0, 0, 1e-7);
    /* 120 degrees about (1,1,1) permutes the axes X -> Y -> Z; the axis need not be unit length */
    mat4 r3 = mat4_rotate(vec3(2, 2, 2), radians(120.0f));
    assert_vec4(mat4_mul_vec4(r3, vec4(1, 0, 0, 0)), 0, 1, 0, 0, 1e-6);
    assert_vec4(mat4_mul_vec4(r3, vec4(0, 1, 0, 0)), 0, 0, 1, 0, 1e-6);
    /* any rotation is orthonormal: R^T R = I */
    mat4 r = mat4_rotate(vec3(0.3f, -0.5f, 0.8f), 2.3f);
    assert_near(mat4_max_diff(mat4_mul(transpose(r), r), mat4_identity()), 0, 1e-6);
}

static void test_look_at(void **state)
{
    (void)state;
    vec3 eye = vec3(1, 2, 3), target = vec3(4, 6, 3); /* 5 units away, level */
    mat4 v = lookAt(eye, target, vec3(0, 0, 1));
    assert_vec4(mat4_mul_vec4(v, vec4_from3(eye, 1)), 0, 0, 0, 1, 1e-6);      /* eye -> origin */
    assert_vec4(mat4_mul_vec4(v, vec4_from3(target, 1)), 0, 0, -5, 1, 1e-5);  /* target -> -Z */
    assert_vec4(mat4_mul_vec4(v, vec4(0, 0, 1, 0)), 0, 1, 0, 0, 1e-6);        /* up -> +Y */
    /* forward (3,4,0)/5 cross up (0,0,1) = (4,-3,0)/5 is +X in view space */
    assert_vec4(mat4_mul_vec4(v, vec4(0.8f, -0.6f, 0, 0)), 1, 0, 0, 0, 1e-6);
    /* a rigid motion: the 3x3 part is orthonormal */
    mat3 r = mat3_from_mat4(v);
    assert_near(dot(r.c[0], r.c[0]), 1, 1e-6);
    assert_near(dot(r.c[0], r.c[1]), 0, 1e-6);
    assert_near(mat3_determinant(r), 1, 1e-6);
}

static void test_perspective(void **state)
{
    (void)state;
    /* fovy 90 degrees: f = 1/tan(45) = 1; aspect 2, near 1, far 10 */
    mat4 p = perspective(radians(90.0f), 2.0f, 1.0f, 10.0f);
    assert_near(p.c[0].x, 0.5, 1e-7);
    assert_near(p.c[1].y, 1.0, 1e-7);
    assert_near(p.c[2].z, -11.0 / 9.0, 1e-6);
    assert_near(p.c[3].z, -20.0 / 9.0, 1e-6);
    assert_true(p.c[2].w == -1.0f && p.c[3].w == 0.0f);
    vec4 n = mat4_mul_vec4(p, vec4(0, 0, -1, 1)), f = mat4_mul_vec4(p, vec4(0, 0, -10, 1));
    assert_near(n.z / n.w, -1.0, 1e-6); /* near plane -> z_ndc = -1 */
    assert_near(f.z / f.w, 1.0, 1e-6);  /* far plane -> +1 */
    assert_near(n.w, 1.0, 0);           /* w = -z_eye */
    /* the top-right corner of the near plane: y = near tan(45) = 1, x = aspect * y = 2 */
    vec4 c = mat4_mul_vec4(p, vec4(2, 1, -1, 1));
    assert_near(c.x / c.w, 1.0, 1e-6);
    assert_near(c.y / c.w, 1.0, 1e-6);
    /* a point half way in depth lands strictly inside (-1, 1) */
    vec4 m = mat4_mul_vec4(p, vec4(0, 0, -5.5f, 1));
    assert_true(m.z / m.w > -1.0f && m.z / m.w < 1.0f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_constructors), cmocka_unit_test(test_scalar_helpers),
        cmocka_unit_test(test_vector_arithmetic), cmocka_unit_test(test_dot_length_normalize),
        cmocka_unit_test(test_cross), cmocka_unit_test(test_reflect),
        cmocka_unit_test(test_mix_clamp_minmax), cmocka_unit_test(test_mat3),
        cmocka_unit_test(test_mat4_basics), cmocka_unit_test(test_mat4_inverse),
        cmocka_unit_test(test_rotate), cmocka_unit_test(test_look_at),
        cmocka_unit_test(test_perspective),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

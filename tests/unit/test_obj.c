/* test_obj.c - the OBJ reader (obj.c) and mesh helpers (mesh.c): face forms, indices, fan
 * triangulation, normals (given, computed, angle-weighted, degenerate), errors with line
 * numbers, and the shipped bunny. Expected values are worked out by hand in the comments. */
#include "testutil.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene/scene.h"

#define PI_D 3.14159265358979323846

static void parse_ok(const char *text, sl_mesh *m)
{
    sl_error err = {0};
    if (!sl_mesh_parse_obj(text, strlen(text), "t.obj", m, &err)) {
        print_error("unexpected error: %s\n", err.msg);
        fail();
    }
    assert_true(sl_mesh_validate(m, "t.obj", &err));
}

/* Parse must fail and the message must contain `want`. */
static void parse_fails(const char *text, const char *want)
{
    sl_mesh m;
    sl_error err = {0};
    bool ok = sl_mesh_parse_obj(text, strlen(text), "t.obj", &m, &err);
    if (ok || !strstr(err.msg, want)) {
        print_error("expected an error containing \"%s\", got %s \"%s\"\n", want, ok ? "success" : "error",
                    err.msg);
        sl_mesh_free(&m);
        fail();
    }
    /* A failed parse leaves an empty mesh. */
    assert_int_equal(m.vertex_count, 0);
    assert_null(m.positions);
}

static void assert_vec3_near(vec3 a, vec3 b, float tol)
{
    assert_near(a.x, b.x, tol);
    assert_near(a.y, b.y, tol);
    assert_near(a.z, b.z, tol);
}

static const char *TRI_HEAD = "v 0 0 0\nv 1 0 0\nv 0 1 0\n"
                              "vt 0 0\nvt 1 0\nvt 0 1\n"
                              "vn 0 0 2\n"; /* not unit: the reader must normalise it */

static void test_face_form_v(void **state)
{
    (void)state;
    char text[256];
    snprintf(text, sizeof text, "%sf 1 2 3\n", TRI_HEAD);
    sl_mesh m;
    parse_ok(text, &m);
    assert_int_equal(m.vertex_count, 3);
    assert_int_equal(m.triangle_count, 1);
    assert_null(m.texcoords); /* no corner named a vt */
    for (int v = 0; v < 3; v++)
        assert_vec3_near(m.normals[v], vec3(0, 0, 1), 0.0f); /* computed: CCW in z = 0 -> +Z exactly */
    assert_vec3_near(m.positions[1], vec3(1, 0, 0), 0.0f);
    sl_mesh_free(&m);
}

static void test_face_form_vt(void **state)
{
    (void)state;
    char text[256];
    snprintf(text, sizeof text, "%sf 1/3 2/2 3/1\n", TRI_HEAD);
    sl_mesh m;
    parse_ok(text, &m);
    assert_int_equal(m.vertex_count, 3);
    assert_non_null(m.texcoords);
    assert_near(m.texcoords[0].x, 0.0f, 0.0f);
    assert_near(m.texcoords[0].y, 1.0f, 0.0f); /* vt 3 */
    assert_near(m.texcoords[1].x, 1.0f, 0.0f); /* vt 2 */
    assert_near(m.texcoords[2].y, 0.0f, 0.0f); /* vt 1 */
    sl_mesh_free(&m);
}

static void test_face_form_vn(void **state)
{
    (void)state;
    char text[256];
    /* The file's normal is +Z*2 for all three; after normalising it is exactly +Z. Use a
     * clockwise triangle so a computed normal (-Z) could not be mistaken for the given one. */
    snprintf(text, sizeof text, "%sf 1//1 3//1 2//1\n", TRI_HEAD);
    sl_mesh m;
    parse_ok(text, &m);
    assert_null(m.texcoords);
    for (int v = 0; v < 3; v++)
        assert_vec3_near(m.normals[v], vec3(0, 0, 1), 0.0f);
    assert_int_equal(m.indices[1], 1);
    assert_vec3_near(m.positions[m.indices[1]], vec3(0, 1, 0), 0.0f);
    sl_mesh_free(&m);
}

static void test_face_form_vtn(void **state)
{
    (void)state;
    char text[256];
    snprintf(text, sizeof text, "%sf 1/1/1 2/2/1 3/3/1\n", TRI_HEAD);
    sl_mesh m;
    parse_ok(text, &m);
    assert_non_null(m.texcoords);
    assert_near(m.texcoords[2].y, 1.0f, 0.0f);
    assert_vec3_near(m.normals[2], vec3(0, 0, 1), 0.0f);
    sl_mesh_free(&m);
}

/* One output vertex per distinct (v, vt, vn): a shared corner is shared, a UV seam splits. */
static void test_unique_vertices(void **state)
{
    (void)state;
    sl_mesh m;
    /* Quad as two triangles sharing positions 1 and 3 with the same vt: 4 vertices. */
    parse_ok("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
             "f 1/1 2/2 3/3\nf 1/1 3/3 4/4\n",
             &m);
    assert_int_equal(m.vertex_count, 4);
    assert_int_equal(m.triangle_count, 2);
    sl_mesh_free(&m);
    /* Same, but the second triangle names position 1 with another vt: 5 vertices. */
    parse_ok("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
             "f 1/1 2/2 3/3\nf 1/4 3/3 4/4\n",
             &m);
    assert_int_equal(m.vertex_count, 5);
    sl_mesh_free(&m);
}

/* Negative indices count back from the last element defined so far. */
static void test_negative_indices(void **state)
{
    (void)state;
    sl_mesh m;
    parse_ok("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\n"
             "v 5 0 0\nv 6 0 0\nv 5 1 0\nvn 0 0 1\nf -3//-1 -2//-1 -1//-1\n",
             &m);
    assert_int_equal(m.triangle_count, 2);
    assert_vec3_near(m.positions[m.indices[0]], vec3(0, 0, 0), 0.0f);
    assert_vec3_near(m.positions[m.indices[2]], vec3(0, 1, 0), 0.0f);
    assert_vec3_near(m.positions[m.indices[3]], vec3(5, 0, 0), 0.0f); /* -3 after 6 positions = 4 */
    assert_vec3_near(m.positions[m.indices[5]], vec3(5, 1, 0), 0.0f);
    sl_mesh_free(&m);
}

/* Polygons are fans around their first vertex: n corners -> n - 2 triangles (0, i, i+1). */
static void test_fan_triangulation(void **state)
{
    (void)state;
    sl_mesh m;
    parse_ok("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n", &m);
    assert_int_equal(m.triangle_count, 2);
    static const uint32_t quad[6] = {0, 1, 2, 0, 2, 3};
    for (int k = 0; k < 6; k++)
        assert_int_equal(m.indices[k], quad[k]);
    sl_mesh_free(&m);

    parse_ok("v 1 0 0\nv 0.309 0.951 0\nv -0.809 0.588 0\nv -0.809 -0.588 0\nv 0.309 -0.951 0\n"
             "f 1 2 3 4 5\n",
             &m);
    assert_int_equal(m.triangle_count, 3);
    static const uint32_t pentagon[9] = {0, 1, 2, 0, 2, 3, 0, 3, 4};
    for (int k = 0; k < 9; k++)
        assert_int_equal(m.indices[k], pentagon[k]);
    sl_mesh_free(&m);
}

/* A flat quad without normals gets exactly its face normal at every vertex. */
static void test_flat_quad_normals(void **state)
{
    (void)state;
    sl_mesh m;
    /* In the plane x = 2, counter-clockwise seen from +X: face normal exactly (1, 0, 0). */
    parse_ok("v 2 0 0\nv 2 1 0\nv 2 1 1\nv 2 0 1\nf 1 2 3 4\n", &m);
    for (int v = 0; v < 4; v++)
        assert_vec3_near(m.normals[v], vec3(1, 0, 0), 0.0f);
    sl_mesh_free(&m);
    /* A tilted flat quad: the plane x + y + z = 1 -> normal (1,1,1)/sqrt(3), up to float rounding. */
    parse_ok("v 1 0 0\nv 0 1 0\nv -1 1 1\nv 0 0 1\nf 1 2 3 4\n", &m);
    float s = 1.0f / sqrtf(3.0f);
    for (int v = 0; v < 4; v++)
        assert_vec3_near(m.normals[v], vec3(s, s, s), 1e-6f);
    sl_mesh_free(&m);
}

/* Angle weighting on a configuration where it differs from area weighting and from a plain
 * average. At O = (0,0,0): T1 = (O, (1,0,0), (0,1,0)) has normal +Z and a 90 degree corner at
 * O; T2 = (O, (1,0,1), (1,0,0)) has normal (1,0,1)x(1,0,0) = (0,1,0) and a 45 degree corner
 * at O. Both have area 1/2, so area weighting (and averaging) would give (0,1,1)/sqrt(2);
 * angle weighting gives normalize(pi/2 (0,0,1) + pi/4 (0,1,0)) = (0,1,2)/sqrt(5). */
static void test_angle_weighted_normals(void **state)
{
    (void)state;
    sl_mesh m;
    parse_ok("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 0 1\nf 1 2 3\nf 1 4 2\n", &m);
    /* Vertex 0 is O (first corner of the first face). */
    assert_vec3_near(m.positions[0], vec3(0, 0, 0), 0.0f);
    float r5 = 1.0f / sqrtf(5.0f);
    assert_vec3_near(m.normals[0], vec3(0, r5, 2 * r5), 1e-6f);

    /* The public function agrees on the same mesh. */
    for (int v = 0; v < m.vertex_count; v++)
        m.normals[v] = vec3(0, 0, 0);
    sl_mesh_compute_normals(&m);
    assert_vec3_near(m.normals[0], vec3(0, r5, 2 * r5), 1e-6f);
    /* Vertex (1,0,0) has the corner angles the other way round: 45 degrees in T1 (between
     * (-1,1,0) and (-1,0,0)) and 90 in T2 (between (-1,0,0) and (0,0,1)): (0,2,1)/sqrt(5). */
    assert_vec3_near(m.normals[1], vec3(0, 2 * r5, r5), 1e-6f);
    sl_mesh_free(&m);
}

/* Computed normals accumulate per OBJ position, so a UV seam (same v, different vt) does
 * not split the shading: both copies get the same normal. */
static void test_normals_across_uv_seam(void **state)
{
    (void)state;
    sl_mesh m;
    parse_ok("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 0 1\nvt 0 0\nvt 1 1\n"
             "f 1/1 2/1 3/1\nf 1/2 4/2 2/2\n",
             &m);
    /* Vertices: (1,1) (2,1) (3,1) (1,2) (4,2) (2,2) -> 6 distinct. */
    assert_int_equal(m.vertex_count, 6);
    float r5 = 1.0f / sqrtf(5.0f);
    assert_vec3_near(m.normals[0], vec3(0, r5, 2 * r5), 1e-6f);
    assert_vec3_near(m.normals[3], vec3(0, r5, 2 * r5), 1e-6f);
    sl_mesh_free(&m);
}

/* A zero normal in the file is replaced by a computed one; degenerate faces never give NaN. */
static void test_degenerate_normals(void **state)
{
    (void)state;
    sl_mesh m;
    parse_ok("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 0\nf 1//1 2//1 3//1\n", &m);
    for (int v = 0; v < 3; v++)
        assert_vec3_near(m.normals[v], vec3(0, 0, 1), 0.0f);
    sl_mesh_free(&m);
    /* All three points on a line: no face direction at all -> the +Z fallback, finite. */
    parse_ok("v 0 0 0\nv 1 1 1\nv 2 2 2\nf 1 2 3\n", &m);
    for (int v = 0; v < 3; v++)
        assert_vec3_near(m.normals[v], vec3(0, 0, 1), 0.0f);
    sl_mesh_free(&m);
    /* The same triangle twice with opposite windings: the contributions cancel exactly. */
    parse_ok("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 3 2\n", &m);
    for (int v = 0; v < 3; v++)
        assert_true(isfinite(m.normals[v].x) && isfinite(m.normals[v].y) && isfinite(m.normals[v].z));
    sl_mesh_free(&m);
    /* Huge but finite coordinates: edges overflow float if squared naively. */
    parse_ok("v 0 0 0\nv 3e38 0 0\nv 0 3e38 0\nf 1 2 3\n", &m);
    for (int v = 0; v < 3; v++)
        assert_vec3_near(m.normals[v], vec3(0, 0, 1), 1e-6f);
    sl_mesh_free(&m);
}

/* Statements softlight does not use are accepted; so are CRLF, trailing comments, tabs, vertex
 * colours after v x y z, and a 3-component vt. */
static void test_ignored_statements(void **state)
{
    (void)state;
    sl_mesh m;
    parse_ok("# header\r\nmtllib x.mtl\r\no thing\r\ng group\r\ns 1\r\nusemtl red\r\n"
             "v 0 0 0 1 0 0\r\nv\t1 0 0 # colour-less\r\nv 0 1 0\r\nvt 0.5 0.5 0\r\n"
             "l 1 2\r\np 1\r\ncurv 0 1 2\r\nvp 0.5\r\nf 1/1 2/1 3/1\r\n",
             &m);
    assert_int_equal(m.triangle_count, 1);
    assert_vec3_near(m.positions[1], vec3(1, 0, 0), 0.0f);
    assert_near(m.texcoords[0].x, 0.5f, 0.0f);
    sl_mesh_free(&m);
}

static void test_index_errors(void **state)
{
    (void)state;
    parse_fails("v 0 0 0\nv 1 0 0\nv 0 1 0\n# comment\nf 1 2 4\n", "t.obj:5: face index 4 out of range (1..3)");
    parse_fails("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n", "t.obj:4: face index -4 out of range (-3..-1)");
    parse_fails("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "t.obj:4: face index 0 out of range");
    parse_fails("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/2 2/1 3/1\n",
                "t.obj:5: texture coordinate index 2 out of range (1..1)");
    parse_fails("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//1 2//1 3//1\n",
                "t.obj:4: normal index 1 out of range (the file defines none)");
    parse_fails("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999999999999\n", "t.obj:4: face index");
}

static void test_syntax_errors(void **state)
{
    (void)state;
    parse_fails("v 0 0 0\nv 1 0\n", "t.obj:2: expected 3 numbers, got 2");
    parse_fails("v 0 0 zero\n", "t.obj:1: expected a number, got 'zero'");
    parse_fails("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n", "t.obj:4: a face needs at least 3 vertices, got 2");
    parse_fails("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/1/1/1 2 3\n", "t.obj:4: malformed face vertex");
    parse_fails("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/ 2 3\n", "t.obj:4: malformed face vertex");
    parse_fails("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1// 2 3\n", "t.obj:4: malformed face vertex");
    parse_fails("v 0 0 0\nv 1 0 0\nv 0 1 0\nf a b c\n", "t.obj:4: face index: expected an integer, got 'a'");
    parse_fails("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1x 2 3\n", "t.obj:4: face index: expected an integer");
}

static void test_non_finite_rejected(void **state)
{
    (void)state;
    parse_fails("v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n", "t.obj:2: number is not finite");
    parse_fails("v 0 0 0\nv 1 0 0\nv 0 inf 0\nf 1 2 3\n", "t.obj:3: number is not finite");
    parse_fails("v 0 0 0\nv 1e39 0 0\nv 0 1 0\nf 1 2 3\n", "t.obj:2: number is not finite"); /* > FLT_MAX */
    parse_fails("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 NaN 1\nf 1//1 2//1 3//1\n", "t.obj:4: number is not finite");
}

static void test_empty_file(void **state)
{
    (void)state;
    parse_fails("", "t.obj: no faces");
    parse_fails("# only a comment\n\n", "t.obj: no faces");
    parse_fails("v 0 0 0\nv 1 0 0\nv 0 1 0\n", "t.obj: no faces");
    /* A NUL byte means the input is not text. */
    sl_mesh m;
    sl_error err = {0};
    static const char bin[] = "v 0 0 0\nv 1\0 0 0\n";
    assert_false(sl_mesh_parse_obj(bin, sizeof bin - 1, "t.obj", &m, &err));
    assert_non_null(strstr(err.msg, "t.obj:2: NUL byte"));
}

/* A UTF-8 byte-order mark (Windows editors write one) is skipped,
 * so the first vertex is kept: bounds max must be (1,1,0), not (1,1,1) from vertex 4. */
static void test_utf8_bom(void **state)
{
    (void)state;
    sl_mesh m;
    parse_ok("\xef\xbb\xbfv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\n", &m);
    assert_int_equal(m.vertex_count, 3);
    for (int v = 0; v < 3; v++)
        assert_near(m.positions[v].z, 0.0f, 0.0f);
    sl_mesh_free(&m);
    /* BOM + CRLF: an error on line 1 is reported on line 1. */
    parse_fails("\xef\xbb\xbfv 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nf 1 2 3\r\n", "t.obj:1: expected 3 numbers, got 2");
    /* A BOM anywhere else is bytes glued to a keyword: an error naming the line, masked. */
    parse_fails("v 0 0 0\nv 1 0 0\n\xef\xbb\xbfv 0 1 0\nf 1 2 3\n", "t.obj:3: unknown statement '???v'");
}

/* An unknown statement is skipped only when it looks like a keyword; a known keyword with junk
 * glued to it must not pass silently. */
static void test_junk_keywords(void **state)
{
    (void)state;
    parse_fails("v 0 0 0\nv1 0 0\nv 0 1 0\nf 1 2 3\n", "t.obj:2: unknown statement 'v1'");
    parse_fails("v 0 0 0\nv 1 0 0\nv 0 1 0\nf1 2 3\n", "t.obj:4: unknown statement 'f1'");
    parse_fails("v 0 0 0\nv 1 0 0\nv 0 1 0\nv.5 0 0\nf 1 2 3\n", "t.obj:4: unknown statement 'v.5'");
    parse_fails("v 0 0 0\nv 1 0 0\nv 0 1 0\n\x1b[2Jv 0 0 0\nf 1 2 3\n", "t.obj:4: unknown statement '?[2Jv'");
    /* Keywords of the OBJ specification that softlight does not use are still fine. */
    sl_mesh m;
    parse_ok("v 0 0 0\nv 1 0 0\nv 0 1 0\ncstype bspline\ndeg 3\nshadow_obj s.obj\nc_interp off\nf 1 2 3\n", &m);
    sl_mesh_free(&m);
}

/* Raw input bytes in messages are masked ('?' for what is not printable ASCII). */
static void test_messages_mask_bytes(void **state)
{
    (void)state;
    parse_fails("v 0 0 \x1b]0;x\x07\n", "t.obj:1: expected a number, got '?]0;x?'");
    parse_fails("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 \xff\xfe\n", "face index: expected an integer, got '?" "?'");
    parse_fails("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3/\x01\n", "texture coordinate index: expected an integer, got '?'");
}

/* UTF-16 text is named as such, not as "NUL byte ... not a text file?". */
static void test_utf16(void **state)
{
    (void)state;
    static const char le_bom[] = "\xff\xfev\0 \0" "0\0 \0";
    static const char be_bom[] = "\xfe\xff\0v\0 \0" "0\0 ";
    static const char le[] = "v\0 \0" "0\0 \0" "0\0";
    const struct {
        const char *text;
        size_t size;
        const char *want;
    } cases[] = {
        {le_bom, sizeof le_bom - 1, "t.obj:1: the file is UTF-16 (little-endian"},
        {be_bom, sizeof be_bom - 1, "t.obj:1: the file is UTF-16 (big-endian"},
        {le, sizeof le - 1, "t.obj:1: the file is UTF-16 (little-endian"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        sl_mesh m;
        sl_error err = {0};
        assert_false(sl_mesh_parse_obj(cases[i].text, cases[i].size, "t.obj", &m, &err));
        if (!strstr(err.msg, cases[i].want) || !strstr(err.msg, "UTF-8")) {
            print_error("case %zu: got \"%s\"\n", i, err.msg);
            fail();
        }
    }
}

/* Line endings LF, CRLF and CR-only (old Mac) all end a line, and line numbers count
 * them the same way; a backslash as the last character joins the next line (OBJ spec B1). */
static void test_line_endings_and_continuation(void **state)
{
    (void)state;
    sl_mesh m;
    parse_ok("v 0 0 0\rv 1 0 0\rv 0 1 0\rf 1 2 3\r", &m);
    assert_int_equal(m.triangle_count, 1);
    assert_vec3_near(m.positions[1], vec3(1, 0, 0), 0.0f);
    sl_mesh_free(&m);
    parse_fails("v 0 0 0\rv 1 0 0\r\rv 0 1\rf 1 2 3\r", "t.obj:4: expected 3 numbers, got 2");
    parse_fails("v 0 0 0\r\nv 1 0 0\r\n\rv 0 1\nf 1 2 3\r", "t.obj:4: expected 3 numbers, got 2");

    parse_ok("v 0 0 0\nv 1 \\\n 0 0\nv 0 1 0\nf 1 \\\r\n2 \\\n3\n", &m);
    assert_int_equal(m.triangle_count, 1);
    assert_vec3_near(m.positions[1], vec3(1, 0, 0), 0.0f);
    sl_mesh_free(&m);
    /* An error in a continued statement names its first line; later lines keep their numbers. */
    parse_fails("v 0 0 0\nv 1 \\\n0\nv 0 1 0\nf 1 2 3\n", "t.obj:2: expected 3 numbers, got 2");
    parse_fails("v 0 0 0\nv 1 \\\n0 0\nv 0 1\nf 1 2 3\n", "t.obj:4: expected 3 numbers, got 2");
}

/* An `f` with no corners among good faces is skipped (as assimp and tinyobjloader do);
 * one or two corners are still an error. */
static void test_empty_face(void **state)
{
    (void)state;
    sl_mesh m;
    parse_ok("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf\nf   # nothing\nf 3 2 1\n", &m);
    assert_int_equal(m.triangle_count, 2);
    sl_mesh_free(&m);
    parse_fails("v 0 0 0\nv 1 0 0\nv 0 1 0\nf\n", "t.obj: no faces");
    parse_fails("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1\n", "t.obj:4: a face needs at least 3 vertices, got 1");
}

/* '3.1+e2' is refused with a hint. The common loaders (tinyobjloader, assimp's
 * fast_atof, strtod) stop at '+' and read 3.1, silently dropping what was likely meant as 310. */
static void test_misplaced_exponent(void **state)
{
    (void)state;
    parse_fails("v 3.1+e2 0 0\n", "t.obj:1: expected a number, got '3.1+e2' (an exponent is written 3.1e+2)");
    parse_fails("v 1 2-E3 0\n", "(an exponent is written 2E-3)");
}

/* A face may name positions, texture coordinates and normals defined later in the
 * file (OBJ numbers each kind from the first in the file); negative indices stay relative to
 * what is defined so far. Out of range is still an error on the face's line. */
static void test_forward_references(void **state)
{
    (void)state;
    sl_mesh m;
    parse_ok("f 1/1/1 2/2/1 3/3/1\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\n", &m);
    assert_int_equal(m.triangle_count, 1);
    assert_vec3_near(m.positions[m.indices[1]], vec3(1, 0, 0), 0.0f);
    assert_near(m.texcoords[m.indices[2]].y, 1.0f, 0.0f);
    sl_mesh_free(&m);
    /* -1 is position 1 here; triangles stay in file order. */
    parse_ok("v 0 0 0\nf 1 2 -1\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", &m);
    assert_int_equal(m.triangle_count, 2);
    assert_vec3_near(m.positions[m.indices[2]], vec3(0, 0, 0), 0.0f);
    sl_mesh_free(&m);
    parse_fails("v 0 0 0\nf 1 2 4\nv 1 0 0\nv 0 1 0\n", "t.obj:2: face index 4 out of range (1..3)");
    parse_fails("f 1 2 3\nv 0 0 0\nv 1 0 0\n", "t.obj:1: face index 3 out of range (1..2)");
    parse_fails("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/5 2/5 3/5\nvt 0 0\n",
                "t.obj:4: texture coordinate index 5 out of range (1..1)");
}

/* Signed area in the z = 0 plane of triangle t (positive = counter-clockwise seen from +Z). */
static double tri_area_z(const sl_mesh *m, int t)
{
    vec3 a = m->positions[m->indices[3 * t]], b = m->positions[m->indices[3 * t + 1]],
         c = m->positions[m->indices[3 * t + 2]];
    return 0.5 * ((double)(b.x - a.x) * (c.y - a.y) - (double)(b.y - a.y) * (c.x - a.x));
}

/* Concave faces are ear-clipped: every triangle keeps the face's winding (no negative
 * area, which is what a fan over a concave corner gives) and the areas add up to the face's. */
static void test_concave_l(void **state)
{
    (void)state;
    sl_mesh m;
    /* The L [0,2]x[0,1] u [0,1]x[0,2] (area 3) started at (2,0): the fan's second triangle,
     * (2,0) (1,1) (1,2), is clockwise and the third covers (1.5, 1.5), outside the L. */
    parse_ok("v 2 0 0\nv 2 1 0\nv 1 1 0\nv 1 2 0\nv 0 2 0\nv 0 0 0\nf 1 2 3 4 5 6\n", &m);
    assert_int_equal(m.triangle_count, 4);
    double sum = 0.0;
    for (int t = 0; t < m.triangle_count; t++) {
        assert_true(tri_area_z(&m, t) >= 0.0);
        sum += tri_area_z(&m, t);
    }
    assert_near(sum, 3.0, 1e-12);
    for (int v = 0; v < m.vertex_count; v++)
        assert_vec3_near(m.normals[v], vec3(0, 0, 1), 0.0f);
    sl_mesh_free(&m);
    /* The same L in the plane x = 1, as (y, z) mirrored: clockwise seen from +X, so its normal
     * is -X. The best-fit plane decides the projection. */
    parse_ok("v 1 0 2\nv 1 1 2\nv 1 1 1\nv 1 2 1\nv 1 2 0\nv 1 0 0\nf 1 2 3 4 5 6\n", &m);
    assert_int_equal(m.triangle_count, 4);
    for (int v = 0; v < m.vertex_count; v++)
        assert_vec3_near(m.normals[v], vec3(-1, 0, 0), 0.0f);
    sl_mesh_free(&m);
}

/* A ring with a hole: 33 outer corners (R = 2, counter-clockwise, the first repeated) and
 * 33 inner ones (r = 1, clockwise, the first repeated), joined by a seam: 66 corners that
 * enclose an annulus. A fan from corner 1 fills the hole: the sum of |area| would then exceed
 * the ring's, and triangles would lie in the hole. */
static void test_concave_ring(void **state)
{
    (void)state;
    char text[8192];
    size_t len = 0;
    const int k = 32;
    for (int i = 0; i < k; i++) {
        double a = 2.0 * PI_D * i / k;
        len += (size_t)snprintf(text + len, sizeof text - len, "v %.9f %.9f 0\n", 2.0 * cos(a), 2.0 * sin(a));
    }
    for (int i = 0; i < k; i++) {
        double a = 2.0 * PI_D * i / k;
        len += (size_t)snprintf(text + len, sizeof text - len, "v %.9f %.9f 0\n", cos(a), sin(a));
    }
    len += (size_t)snprintf(text + len, sizeof text - len, "f");
    for (int i = 0; i <= k; i++)
        len += (size_t)snprintf(text + len, sizeof text - len, " %d", i % k + 1);
    for (int i = 0; i <= k; i++)
        len += (size_t)snprintf(text + len, sizeof text - len, " %d", k + (k - i) % k + 1);
    snprintf(text + len, sizeof text - len, "\n");
    sl_mesh m;
    parse_ok(text, &m);
    assert_int_equal(m.triangle_count, 64);
    double sum = 0.0, ring = 0.0;
    for (int i = 0; i < k; i++) /* the polygonal ring's area: 32 outer minus 32 inner wedges */
        ring += 0.5 * (4.0 - 1.0) * sin(2.0 * PI_D / k);
    for (int t = 0; t < m.triangle_count; t++) {
        double area = tri_area_z(&m, t);
        assert_true(area >= 0.0);
        sum += area;
        /* No triangle lies in the hole: its centroid is outside the inner polygon. */
        vec3 c = scale3(add3(add3(m.positions[m.indices[3 * t]], m.positions[m.indices[3 * t + 1]]),
                             m.positions[m.indices[3 * t + 2]]),
                        1.0f / 3.0f);
        assert_true(length3(c) > 0.99f);
    }
    assert_near(sum, ring, 1e-5);
    sl_mesh_free(&m);
}

/* Faces that cannot be triangulated are named, with the corners that cross. */
static void test_bad_polygons(void **state)
{
    (void)state;
    /* A pentagram: every turn is to the left but it winds twice. */
    parse_fails("v 1 0 0\nv 0.309 0.951 0\nv -0.809 0.588 0\nv -0.809 -0.588 0\nv 0.309 -0.951 0\n"
                "f 1 3 5 2 4\n",
                "t.obj:6: face with 5 corners cannot be triangulated: its edges cross (corners 1-2 and 3-4)");
    /* A bow tie whose halves cancel: no area in any plane, yet not a line. */
    parse_fails("v 0 0 0\nv 1 1 0\nv 1 0 0\nv 0 1 0\nf 1 2 3 4\n",
                "t.obj:5: face with 4 corners cannot be triangulated: it encloses no area");
    /* A concave face of more than 4096 corners (a comb: ear clipping is O(n^2)) is refused;
     * a convex one of the same size is not. */
    size_t cap = 64 * 4200, len = 0;
    char *text = malloc(cap);
    assert_non_null(text);
    for (int i = 0; i < 2048; i++)
        len += (size_t)snprintf(text + len, cap - len, "v %d 0 0\nv %d.5 9 0\n", i, i);
    len += (size_t)snprintf(text + len, cap - len, "v 2048 0 0\nv 2048 -1 0\nv 0 -1 0\nf");
    for (int i = 1; i <= 4099; i++)
        len += (size_t)snprintf(text + len, cap - len, " %d", i);
    snprintf(text + len, cap - len, "\n");
    parse_fails(text, "t.obj:4100: face with 4099 corners cannot be triangulated: it is concave and has more than "
                      "4096 corners");
    len = 0;
    for (int i = 0; i < 4098; i++)
        len += (size_t)snprintf(text + len, cap - len, "v %.9f %.9f 0\n", cos(2.0 * PI_D * i / 4098),
                                sin(2.0 * PI_D * i / 4098));
    len += (size_t)snprintf(text + len, cap - len, "f");
    for (int i = 1; i <= 4098; i++)
        len += (size_t)snprintf(text + len, cap - len, " %d", i);
    snprintf(text + len, cap - len, "\n");
    sl_mesh m;
    parse_ok(text, &m);
    assert_int_equal(m.triangle_count, 4096);
    sl_mesh_free(&m);
    free(text);
    /* Corners on one line enclose nothing and draw nothing: accepted as before. */
    parse_ok("v 0 0 0\nv 1 0 0\nv 2 0 0\nv 3 0 0\nf 1 2 3 4\n", &m);
    assert_int_equal(m.triangle_count, 2);
    sl_mesh_free(&m);
}

static void test_load_missing_file(void **state)
{
    (void)state;
    sl_mesh m;
    sl_error err = {0};
    assert_false(sl_mesh_load_obj("scenes/meshes/does-not-exist.obj", &m, &err));
    assert_int_equal(err.code, SL_ERR_IO);
    assert_non_null(strstr(err.msg, "does-not-exist.obj"));
}

/* The shipped bunny: counts from the file (1839 v, 3674 f, no vn, no vt), closed and
 * consistently counter-clockwise outward (positive signed volume). */
static void test_bunny(void **state)
{
    (void)state;
    sl_mesh m;
    sl_error err = {0};
    if (!sl_mesh_load_obj("scenes/meshes/bunny.obj", &m, &err)) {
        print_error("%s\n", err.msg);
        fail();
    }
    assert_true(sl_mesh_validate(&m, "bunny.obj", &err));
    assert_int_equal(m.vertex_count, 1839);
    assert_int_equal(m.triangle_count, 3674);
    assert_null(m.texcoords);
    /* Divergence theorem: V = sum over triangles of a . (b x c) / 6. */
    double volume = 0.0;
    vec3 centre = vec3(0, 0, 0);
    for (int v = 0; v < m.vertex_count; v++)
        centre = add3(centre, scale3(m.positions[v], 1.0f / (float)m.vertex_count));
    for (int t = 0; t < m.triangle_count; t++) {
        vec3 a = m.positions[m.indices[3 * t]], b = m.positions[m.indices[3 * t + 1]],
             c = m.positions[m.indices[3 * t + 2]];
        volume += (double)dot3(a, cross(b, c)) / 6.0;
    }
    assert_true(volume > 150.0); /* the python check of the file gives 194.3 */
    assert_near(volume, 194.288, 0.01);
    /* Computed normals point outward: most agree with (p - centre). */
    int outward = 0;
    for (int v = 0; v < m.vertex_count; v++)
        outward += dot3(m.normals[v], sub3(m.positions[v], centre)) > 0.0f;
    assert_true(outward > m.vertex_count * 9 / 10);
    sl_mesh_free(&m);
}

static void test_validate(void **state)
{
    (void)state;
    sl_mesh m;
    sl_error err = {0};
    parse_ok("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", &m);
    m.indices[2] = 3;
    assert_false(sl_mesh_validate(&m, "m", &err));
    assert_non_null(strstr(err.msg, "m: triangle 0: index 3 out of range (0..2)"));
    m.indices[2] = 2;
    m.normals[1] = vec3(0, 0, 2);
    assert_false(sl_mesh_validate(&m, "m", &err));
    assert_non_null(strstr(err.msg, "vertex 1: normal has length 2"));
    m.normals[1] = vec3(0, 0, NAN);
    assert_false(sl_mesh_validate(&m, "m", &err));
    assert_non_null(strstr(err.msg, "vertex 1: normal is not finite"));
    m.normals[1] = vec3(0, 0, 1);
    m.positions[2].y = INFINITY;
    assert_false(sl_mesh_validate(&m, "m", &err));
    assert_non_null(strstr(err.msg, "vertex 2: position is not finite"));
    sl_mesh_free(&m);
    sl_mesh_free(&m); /* freeing twice is harmless: the mesh was zeroed */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_face_form_v),
        cmocka_unit_test(test_face_form_vt),
        cmocka_unit_test(test_face_form_vn),
        cmocka_unit_test(test_face_form_vtn),
        cmocka_unit_test(test_unique_vertices),
        cmocka_unit_test(test_negative_indices),
        cmocka_unit_test(test_fan_triangulation),
        cmocka_unit_test(test_flat_quad_normals),
        cmocka_unit_test(test_angle_weighted_normals),
        cmocka_unit_test(test_normals_across_uv_seam),
        cmocka_unit_test(test_degenerate_normals),
        cmocka_unit_test(test_ignored_statements),
        cmocka_unit_test(test_index_errors),
        cmocka_unit_test(test_syntax_errors),
        cmocka_unit_test(test_non_finite_rejected),
        cmocka_unit_test(test_empty_file),
        cmocka_unit_test(test_utf8_bom),
        cmocka_unit_test(test_junk_keywords),
        cmocka_unit_test(test_messages_mask_bytes),
        cmocka_unit_test(test_utf16),
        cmocka_unit_test(test_line_endings_and_continuation),
        cmocka_unit_test(test_empty_face),
        cmocka_unit_test(test_misplaced_exponent),
        cmocka_unit_test(test_forward_references),
        cmocka_unit_test(test_concave_l),
        cmocka_unit_test(test_concave_ring),
        cmocka_unit_test(test_bad_polygons),
        cmocka_unit_test(test_load_missing_file),
        cmocka_unit_test(test_bunny),
        cmocka_unit_test(test_validate),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

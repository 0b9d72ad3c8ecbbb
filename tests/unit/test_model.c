/* test_model.c - model import through assimp (scene/model.c): small glTF (.gltf + .bin + .png,
 * and .glb with the image embedded) and OBJ+MTL files written here, and what arrives: a node
 * transform composed and turned Z-up, generated normals, UVs in glTF's convention, tangents,
 * the material's factors and texture references, an embedded image's bytes. Then the bad
 * files, each one line naming the file. Expected values are worked out by
 * hand in the comments. */
#include "testutil.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "raster/gbuffer_textured.h"
#include "scene/model.h"
#include "scene/scene_internal.h"

#include <sys/stat.h>

/* One triangle (0,0,0), (1,0,0), (0,1,0) in glTF's Y-up object space, UVs (0,0), (0.25,0.75),
 * (0,1), indices 0 1 2 as unsigned shorts: 36 + 24 + 6 bytes, padded to 68. */
#define BIN_SIZE 68
static void triangle_bin(unsigned char out[BIN_SIZE], float nan_x, unsigned short bad_index)
{
    const float pos[9] = {nan_x, 0, 0, 1, 0, 0, 0, 1, 0};
    const float uv[6] = {0, 0, 0.25f, 0.75f, 0, 1};
    const unsigned short idx[4] = {0, 1, bad_index, 0};
    memcpy(out, pos, 36);
    memcpy(out + 36, uv, 24);
    memcpy(out + 60, idx, 8);
}

/* A glTF document around that triangle. `nodes` and `buffer` vary per test; the scene's root
 * node is 0. Material: baseColorFactor (0.8, 0.4, 0.2, 1), metallic 0.25, roughness 0.6, base
 * colour and metallic-roughness textures from image 0, MASK at 0.3, double-sided. */
static void gltf_text(char *out, size_t cap, const char *nodes, const char *buffer, const char *images)
{
    /* A node 2, if `nodes` has one, is a root too (the camera test's). */
    bool third = strstr(nodes, "\"camera\"") != NULL;
    snprintf(out, cap,
             "{\"asset\": {\"version\": \"2.0\"}, \"scene\": 0, \"scenes\": [{\"nodes\": [0%s]}],\n"
             " %s\n"
             " \"nodes\": %s,\n"
             " \"meshes\": [{\"primitives\": [{\"attributes\": {\"POSITION\": 0, \"TEXCOORD_0\": 1},"
             " \"indices\": 2, \"material\": 0}]}],\n"
             " \"materials\": [{\"name\": \"clay\", \"pbrMetallicRoughness\": {\"baseColorFactor\": [0.8, 0.4, 0.2, 1],"
             " \"metallicFactor\": 0.25, \"roughnessFactor\": 0.6, \"baseColorTexture\": {\"index\": 0},"
             " \"metallicRoughnessTexture\": {\"index\": 0}}, \"alphaMode\": \"MASK\", \"alphaCutoff\": 0.3,"
             " \"doubleSided\": true}],\n"
             " \"textures\": [{\"source\": 0, \"sampler\": 0}],\n"
             " \"samplers\": [{\"magFilter\": 9728, \"wrapS\": 33071}],\n"
             " \"images\": %s,\n"
             " \"accessors\": [{\"bufferView\": 0, \"componentType\": 5126, \"count\": 3, \"type\": \"VEC3\","
             " \"min\": [0, 0, 0], \"max\": [1, 1, 0]},\n"
             "   {\"bufferView\": 1, \"componentType\": 5126, \"count\": 3, \"type\": \"VEC2\"},\n"
             "   {\"bufferView\": 2, \"componentType\": 5123, \"count\": 3, \"type\": \"SCALAR\"}],\n"
             " \"bufferViews\": [{\"buffer\": 0, \"byteOffset\": 0, \"byteLength\": 36},\n"
             "   {\"buffer\": 0, \"byteOffset\": 36, \"byteLength\": 24},\n"
             "   {\"buffer\": 0, \"byteOffset\": 60, \"byteLength\": 6}%s],\n"
             " \"buffers\": [%s]}\n",
             third ? ", 2" : "",
             third ? "\"cameras\": [{\"type\": \"perspective\", \"perspective\": {\"yfov\": 0.8, "
                     "\"aspectRatio\": 1.5, \"znear\": 0.1, \"zfar\": 100}}]," : "",
             nodes, images, strstr(images, "bufferView") ? ",\n {\"buffer\": 0, \"byteOffset\": 68, \"byteLength\": PNGLEN}" : "",
             buffer);
}

/* Parent translates (1, 2, 3), child (holding the mesh) scales by 2. */
static const char *NODES = "[{\"translation\": [1, 2, 3], \"children\": [1]}, {\"scale\": [2, 2, 2], \"mesh\": 0}]";

/* A 2x2 RGB PNG: texel (0,0) is sRGB (255, 128, 0). */
static unsigned char *png_bytes(size_t *size)
{
    sl_image img;
    sl_error err = {0};
    assert_true(sl_image_alloc(&img, 2, 2, 3, &err));
    for (int i = 0; i < 12; i++)
        img.data[i] = 0.5f;
    /* the encoder takes display values: code c is c / 255 */
    img.data[0] = 1.0f, img.data[1] = 128.0f / 255.0f, img.data[2] = 0.0f;
    unsigned char *bytes = NULL;
    assert_true(sl_image_encode_png(&img, &bytes, size, &err));
    sl_image_free(&img);
    return bytes;
}

static void write_gltf_files(const char *name, const char *nodes, unsigned char *bin)
{
    char text[4096], buffer[256];
    snprintf(buffer, sizeof buffer, "{\"uri\": \"%s.bin\", \"byteLength\": %d}", name, BIN_SIZE);
    gltf_text(text, sizeof text, nodes, buffer, "[{\"uri\": \"tex.png\"}]");
    char file[64];
    snprintf(file, sizeof file, "%s.gltf", name);
    test_write_bytes(test_tmpfile(file), text, strlen(text));
    snprintf(file, sizeof file, "%s.bin", name);
    test_write_bytes(test_tmpfile(file), bin, BIN_SIZE);
}

static void load_ok(const char *path, sl_model *m)
{
    sl_error err = {0};
    if (!sl_model_load(path, m, &err)) {
        print_error("unexpected error: %s\n", err.msg);
        fail();
    }
}

static void load_fails(const char *path, const char *want)
{
    sl_model m;
    sl_error err = {0};
    bool ok = sl_model_load(path, &m, &err);
    const char *base = strrchr(path, '/') + 1;
    if (getenv("SL_TEST_VERBOSE"))
        printf("%s\n", err.msg);
    if (ok || !strstr(err.msg, want) || !strstr(err.msg, base) || strchr(err.msg, '\n')) {
        print_error("%s: expected one line naming the file and containing \"%s\", got %s \"%s\"\n", path, want,
                    ok ? "success" : "error", err.msg);
        if (ok)
            sl_model_free(&m);
        fail();
    }
    assert_int_equal(m.mesh_count, 0);
    assert_null(m.meshes);
}

/* The vertex of mesh 0 at object-space position p. */
static int vertex_at(const sl_mesh *mesh, vec3 p)
{
    for (int v = 0; v < mesh->vertex_count; v++)
        if (length3(sub3(mesh->positions[v], p)) < 1e-6f)
            return v;
    fail_msg("no vertex at (%g, %g, %g)", (double)p.x, (double)p.y, (double)p.z);
    return -1;
}

static void test_gltf_with_bin_and_png(void **state)
{
    (void)state;
    unsigned char bin[BIN_SIZE];
    triangle_bin(bin, 0.0f, 2);
    write_gltf_files("tri", NODES, bin);
    size_t png_size;
    unsigned char *png = png_bytes(&png_size);
    test_write_bytes(test_tmpfile("tex.png"), png, png_size);
    free(png);

    sl_model m;
    load_ok(test_tmpfile("tri.gltf"), &m);
    assert_int_equal(m.mesh_count, 1);
    assert_int_equal(m.instance_count, 1);
    const sl_mesh *mesh = &m.meshes[0].mesh;
    assert_int_equal(mesh->vertex_count, 3);
    assert_int_equal(mesh->triangle_count, 1);

    /* Node transform: Z-up * T(1,2,3) * S(2). Vertex (1,0,0): scaled (2,0,0), translated
     * (3,2,3), then (x, y, z) -> (x, -z, y): (3, -3, 2). */
    vec3 w = xyz(mat4_mul_vec4(m.instances[0].world, vec4(1, 0, 0, 1)));
    assert_near(w.x, 3.0f, 1e-5f);
    assert_near(w.y, -3.0f, 1e-5f);
    assert_near(w.z, 2.0f, 1e-5f);

    /* No normals in the file: generated from the face, +Z in object space. */
    for (int v = 0; v < 3; v++) {
        assert_near(mesh->normals[v].z, 1.0f, 1e-6f);
    }
    /* UVs as glTF writes them (assimp's flip undone): (0.25, 0.75) at (1,0,0). */
    int v1 = vertex_at(mesh, vec3(1, 0, 0));
    assert_non_null(mesh->texcoords);
    assert_near(mesh->texcoords[v1].x, 0.25f, 1e-6f);
    assert_near(mesh->texcoords[v1].y, 0.75f, 1e-6f);
    /* Tangent along +u: u grows along (1,0,0) with v fixed? From the UVs: dP1 = (1,0,0) with
     * dUV1 = (0.25, 0.75), dP2 = (0,1,0) with dUV2 = (0, 1); T = (dP1 dv2 - dP2 dv1) / det,
     * det = 0.25*1 - 0*0.75 = 0.25: T = ((1,0,0) - 0.75 (0,1,0)) / 0.25 ~ (1, -0.75, 0),
     * normalised (0.8, -0.6, 0). assimp's "v" is flipped, which flips the bitangent: w = -1
     * relative to N x T; the tangent's direction along u is the same. */
    assert_non_null(m.meshes[0].mesh.tangents);
    vec4 t = m.meshes[0].mesh.tangents[v1];
    assert_near(t.x, 0.8f, 1e-4f);
    assert_near(t.y, -0.6f, 1e-4f);
    assert_near(t.z, 0.0f, 1e-6f);
    assert_true(t.w == 1.0f || t.w == -1.0f);

    /* The material's factors. */
    const sl_model_material *mat = &m.materials[m.meshes[0].material];
    assert_string_equal(mat->name, "clay");
    assert_int_equal(mat->kind, SL_MODEL_MAT_METALLIC_ROUGHNESS);
    assert_near(mat->base_color.x, 0.8f, 1e-6f);
    assert_near(mat->base_color.y, 0.4f, 1e-6f);
    assert_near(mat->base_color.z, 0.2f, 1e-6f);
    assert_near(mat->metallic, 0.25f, 1e-6f);
    assert_near(mat->roughness, 0.6f, 1e-6f);
    assert_int_equal(mat->alpha_mode, SL_ALPHA_MASK);
    assert_near(mat->alpha_cutoff, 0.3f, 1e-6f);
    assert_true(mat->double_sided);
    /* Both slots name the one image file, shared; its sampler came through. */
    assert_int_equal(m.image_count, 1);
    assert_int_equal(mat->base_color_tex.image, 0);
    assert_int_equal(mat->metallic_roughness_tex.image, 0);
    assert_int_equal(mat->normal_tex.image, -1);
    assert_int_equal(mat->base_color_tex.sampler.wrap_s, 33071);
    assert_int_equal(mat->base_color_tex.sampler.mag_filter, 9728);
    assert_string_equal(m.images[0].path, test_tmpfile("tex.png"));
    assert_null(m.images[0].bytes);
    assert_false(m.has_camera);
    sl_model_free(&m);
}

/* The same triangle as .glb: JSON chunk, BIN chunk with the PNG after the geometry. */
static unsigned char *glb_bytes(size_t *size, const unsigned char *png, size_t png_size)
{
    unsigned char bin[BIN_SIZE];
    triangle_bin(bin, 0.0f, 2);
    size_t bin_len = (BIN_SIZE + png_size + 3) & ~(size_t)3;
    char buffer[64], json[4096], fixed[4096];
    snprintf(buffer, sizeof buffer, "{\"byteLength\": %zu}", bin_len);
    gltf_text(json, sizeof json, NODES, buffer, "[{\"bufferView\": 3, \"mimeType\": \"image/png\"}]");
    /* The image's byteLength. */
    char *at = strstr(json, "PNGLEN");
    snprintf(fixed, sizeof fixed, "%.*s%zu%s", (int)(at - json), json, png_size, at + 6);
    size_t json_len = (strlen(fixed) + 3) & ~(size_t)3;
    *size = 12 + 8 + json_len + 8 + bin_len;
    unsigned char *out = calloc(1, *size);
    uint32_t head[3] = {0x46546C67u, 2, (uint32_t)*size}, chunk[2] = {(uint32_t)json_len, 0x4E4F534Au};
    memcpy(out, head, 12);
    memcpy(out + 12, chunk, 8);
    memset(out + 20, ' ', json_len);
    memcpy(out + 20, fixed, strlen(fixed));
    uint32_t bchunk[2] = {(uint32_t)bin_len, 0x004E4942u};
    memcpy(out + 20 + json_len, bchunk, 8);
    memcpy(out + 28 + json_len, bin, BIN_SIZE);
    memcpy(out + 28 + json_len + BIN_SIZE, png, png_size);
    return out;
}

static void test_glb_embedded_image(void **state)
{
    (void)state;
    size_t png_size, size;
    unsigned char *png = png_bytes(&png_size);
    unsigned char *glb = glb_bytes(&size, png, png_size);
    test_write_bytes(test_tmpfile("tri.glb"), glb, size);
    sl_model m;
    load_ok(test_tmpfile("tri.glb"), &m);
    assert_int_equal(m.image_count, 1);
    const sl_model_image *im = &m.images[0];
    assert_string_equal(im->path, "");
    assert_int_equal(im->embedded, 0);
    assert_string_equal(im->format, "png");
    assert_int_equal(im->width, 0); /* encoded, not decoded */
    assert_int_equal(im->size, png_size);
    assert_memory_equal(im->bytes, png, png_size);
    assert_int_equal(m.materials[0].base_color_tex.image, 0);
    vec3 w = xyz(mat4_mul_vec4(m.instances[0].world, vec4(1, 0, 0, 1)));
    assert_near(w.y, -3.0f, 1e-5f);

    /* From memory (the fuzz target's path): the same model. */
    sl_model mm;
    sl_error err = {0};
    assert_true(sl_model_load_memory(glb, size, "glb", "mem.glb", &mm, &err));
    assert_int_equal(mm.image_count, 1);
    assert_memory_equal(mm.images[0].bytes, png, png_size);
    sl_model_free(&mm);

    /* Truncated: every cut of the file is refused with one line (or, if a cut leaves a
     * valid file, loads); none may crash. The middle one is refused. */
    test_write_bytes(test_tmpfile("cut.glb"), glb, size / 2);
    load_fails(test_tmpfile("cut.glb"), "truncated .glb");
    for (size_t n = 0; n < size; n += 7) {
        sl_model c;
        if (sl_model_load_memory(glb, n, "glb", "cut.glb", &c, &err))
            sl_model_free(&c);
    }

    /* A mimeType without '/' (assimp 5.2 reads past it: a crash found by fuzz_model): refused
     * by gltf_check.c with the JSON path. Same length, so the .glb's chunk lengths still hold. */
    size_t at = 0;
    while (at + 9 <= size && memcmp(glb + at, "image/png", 9) != 0)
        at++;
    assert_true(at + 9 <= size);
    glb[at + 5] = '0';
    assert_false(sl_model_load_memory(glb, size, "glb", "mime.glb", &mm, &err));
    assert_msg_contains(err, "mime.glb: images[0].mimeType: expected \"image/png\" or \"image/jpeg\"");
    free(glb);
    free(png);
    sl_model_free(&m);
}

static void test_obj_mtl(void **state)
{
    (void)state;
    const char *obj = "mtllib t.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                      "usemtl brass\nf 1/1 2/2 3/3 4/4\n";
    const char *mtl = "newmtl brass\nKd 0.5 0.25 0.125\nKs 0.9 0.8 0.7\nNs 250\nmap_Kd tex.png\n";
    test_write_bytes(test_tmpfile("t.obj"), obj, strlen(obj));
    test_write_bytes(test_tmpfile("t.mtl"), mtl, strlen(mtl));
    size_t png_size;
    unsigned char *png = png_bytes(&png_size);
    test_write_bytes(test_tmpfile("tex.png"), png, png_size);
    free(png);
    sl_model m;
    load_ok(test_tmpfile("t.obj"), &m);
    /* The quad, triangulated, with its 4 corners shared. */
    assert_int_equal(m.mesh_count, 1);
    assert_int_equal(m.meshes[0].mesh.triangle_count, 2);
    assert_int_equal(m.meshes[0].mesh.vertex_count, 4);
    const sl_model_material *mat = &m.materials[m.meshes[0].material];
    assert_string_equal(mat->name, "brass");
    assert_int_equal(mat->kind, SL_MODEL_MAT_PHONG);
    assert_near(mat->kd.x, 0.5f, 1e-6f);
    assert_near(mat->kd.z, 0.125f, 1e-6f);
    assert_near(mat->ks.y, 0.8f, 1e-6f);
    assert_near(mat->ns, 250.0f, 1e-4f);
    assert_int_equal(mat->base_color_tex.image, 0);
    assert_string_equal(m.images[0].path, test_tmpfile("tex.png"));
    /* OBJ's vt (1,1) (v up) is glTF's (1,0): the image's first row. */
    const sl_mesh *mesh = &m.meshes[0].mesh;
    int v = vertex_at(mesh, vec3(1, 1, 0));
    assert_near(mesh->texcoords[v].x, 1.0f, 1e-6f);
    assert_near(mesh->texcoords[v].y, 0.0f, 1e-6f);
    /* The bunny's normals are given; this quad's are generated: object +Z. */
    assert_near(mesh->normals[v].z, 1.0f, 1e-6f);
    sl_model_free(&m);
}

/* The file's first camera: glTF's at its node's origin looking down -Z, +Y up, yfov 0.8 rad.
 * Node at (0, 0, 5) Y-up is (0, -5, 0) Z-up, looking along +Y (from -Z), up +Z. */
static void test_gltf_camera(void **state)
{
    (void)state;
    unsigned char bin[BIN_SIZE];
    triangle_bin(bin, 0.0f, 2);
    write_gltf_files("cam", "[{\"mesh\": 0}, {}, {\"camera\": 0, \"translation\": [0, 0, 5]}]", bin);
    sl_model m;
    load_ok(test_tmpfile("cam.gltf"), &m);
    assert_true(m.has_camera);
    assert_near(m.camera.eye.x, 0.0f, 1e-6f);
    assert_near(m.camera.eye.y, -5.0f, 1e-6f);
    assert_near(m.camera.eye.z, 0.0f, 1e-6f);
    vec3 dir = sub3(m.camera.target, m.camera.eye);
    assert_near(dir.y, 1.0f, 1e-6f);
    assert_near(m.camera.up.z, 1.0f, 1e-6f);
    assert_near(m.camera.fovy_deg, 0.8 * 180.0 / 3.14159265358979, 1e-3);
    assert_near(m.camera.znear, 0.1f, 1e-6f);
    sl_model_free(&m);

    /* The default scene around it takes that camera. */
    sl_scene scene;
    sl_error err = {0};
    assert_true(sl_scene_load(test_tmpfile("cam.gltf"), &scene, &err));
    assert_near(scene.camera.eye.y, -5.0f, 1e-6f);
    assert_int_equal(scene.object_count, 1);
    /* Metallic-roughness as GGX, per texel (the file has a metallicRoughnessTexture): kd holds the
     * base colour 0.8, metallic 0.25 and roughness 0.6 the factors. */
    const sl_material *mat = &scene.materials[scene.objects[0].material];
    assert_int_equal(mat->brdf, SL_BRDF_GGX);
    assert_near(mat->kd.x, 0.8f, 1e-6f);
    assert_near(mat->metallic, 0.25f, 1e-6f);
    assert_near(mat->roughness, 0.6f, 1e-6f);
    assert_true(mat->maps[SL_MAP_METALLIC_ROUGHNESS].set);
    sl_scene_free(&scene);
}

/* The camera of an ASE and of a LightWave scene, both at 10 units on -Y (Z-up) and turned
 * towards the origin: they look along +Y with +Z up. Their importers leave aiCamera's look-at at
 * its default +Z for cameras that look down their node's -Z. */
static void assert_camera_towards_origin(const char *path)
{
    sl_model m;
    load_ok(path, &m);
    assert_true(m.has_camera);
    assert_near(m.camera.eye.x, 0.0f, 1e-5f);
    assert_near(m.camera.eye.y, -10.0f, 1e-5f);
    assert_near(m.camera.eye.z, 0.0f, 1e-5f);
    vec3 dir = sub3(m.camera.target, m.camera.eye);
    assert_near(dir.y, 1.0f, 1e-5f);
    assert_near(m.camera.up.z, 1.0f, 1e-5f);
    sl_model_free(&m);
}

static void test_ase_lws_camera(void **state)
{
    (void)state;
    /* ASE (3ds Max, Z-up): the camera's node maps local -Z to +Y and local +Y to +Z. */
    static const char ase[] =
        "*3DSMAX_ASCIIEXPORT 200\n"
        "*GEOMOBJECT {\n *NODE_NAME \"Tri\"\n *NODE_TM {\n  *NODE_NAME \"Tri\"\n  *TM_ROW0 1 0 0\n"
        "  *TM_ROW1 0 1 0\n  *TM_ROW2 0 0 1\n  *TM_ROW3 0 0 0\n }\n *MESH {\n  *TIMEVALUE 0\n"
        "  *MESH_NUMVERTEX 3\n  *MESH_NUMFACES 1\n  *MESH_VERTEX_LIST {\n   *MESH_VERTEX 0 -1 0 -1\n"
        "   *MESH_VERTEX 1 1 0 -1\n   *MESH_VERTEX 2 0 0 1\n  }\n  *MESH_FACE_LIST {\n"
        "   *MESH_FACE 0: A: 0 B: 1 C: 2 AB: 1 BC: 1 CA: 1 *MESH_SMOOTHING 1 *MESH_MTLID 0\n  }\n }\n}\n"
        "*CAMERAOBJECT {\n *NODE_NAME \"Camera01\"\n *CAMERA_TYPE Free\n *NODE_TM {\n"
        "  *NODE_NAME \"Camera01\"\n  *TM_ROW0 1 0 0\n  *TM_ROW1 0 0 1\n  *TM_ROW2 0 -1 0\n"
        "  *TM_ROW3 0 -10 0\n }\n *CAMERA_SETTINGS {\n  *TIMEVALUE 0\n  *CAMERA_NEAR 0.1\n"
        "  *CAMERA_FAR 1000\n  *CAMERA_FOV 0.7854\n  *CAMERA_TDIST 10\n }\n}\n";
    test_write_bytes(test_tmpfile("cam.ase"), ase, sizeof ase - 1);
    assert_camera_towards_origin(test_tmpfile("cam.ase"));

    /* LightWave (left-handed, Y-up): a triangle object (LWO2: a layer, three points, one face)
     * and a camera at z = -10 with no rotation, which looks down LightWave's +Z. */
    static const unsigned char lwo[] = {
        'F', 'O', 'R', 'M', 0, 0, 0, 0x5e, 'L', 'W', 'O', '2',
        'L', 'A', 'Y', 'R', 0, 0, 0, 0x12, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, /* 18 bytes */
        'P', 'N', 'T', 'S', 0, 0, 0, 0x24,
        0xbf, 0x80, 0, 0, 0xbf, 0x80, 0, 0, 0, 0, 0, 0, /* -1 -1 0 */
        0x3f, 0x80, 0, 0, 0xbf, 0x80, 0, 0, 0, 0, 0, 0, /*  1 -1 0 */
        0, 0, 0, 0, 0x3f, 0x80, 0, 0, 0, 0, 0, 0,       /*  0  1 0 */
        'P', 'O', 'L', 'S', 0, 0, 0, 0x0c, 'F', 'A', 'C', 'E', 0, 3, 0, 0, 0, 1, 0, 2};
    test_write_bytes(test_tmpfile("tri.lwo"), lwo, sizeof lwo);
    char lws[2048];
    int n = snprintf(lws, sizeof lws, "LWSC\n3\n\nLoadObjectLayer 1 tri.lwo\n\nAddCamera 30000000\n"
                                      "CameraName Camera\nCameraMotion\nNumChannels 9\n");
    const float channel[9] = {0, 0, -10, 0, 0, 0, 1, 1, 1};
    for (int c = 0; c < 9; c++)
        n += snprintf(lws + n, sizeof lws - (size_t)n,
                      "Channel %d\n{ Envelope\n  1\n  Key %g 0 0 0 0 0 0 0 0\n  Behaviors 1 1\n}\n", c,
                      (double)channel[c]);
    test_write_bytes(test_tmpfile("cam.lws"), lws, (size_t)n);
    assert_camera_towards_origin(test_tmpfile("cam.lws"));
}

/* A scene object {"model": ...}: its transform on top of the node's, its material overriding. */
static void test_scene_model_object(void **state)
{
    (void)state;
    unsigned char bin[BIN_SIZE];
    triangle_bin(bin, 0.0f, 2);
    write_gltf_files("obj", NODES, bin);
    size_t png_size;
    unsigned char *png = png_bytes(&png_size);
    test_write_bytes(test_tmpfile("tex.png"), png, png_size);
    free(png);
    const char *json = "{\"materials\": {\"red\": {\"kd\": [0.8, 0, 0]}},\n"
                       " \"objects\": [{\"model\": \"obj.gltf\", \"transform\": {\"translate\": [10, 0, 0]}},\n"
                       "             {\"model\": \"obj.gltf\", \"material\": \"red\"}, {\"shape\": \"plane\"}]}";
    test_write_bytes(test_tmpfile("model-scene.json"), json, strlen(json));
    sl_scene scene;
    sl_error err = {0};
    if (!sl_scene_load(test_tmpfile("model-scene.json"), &scene, &err))
        fail_msg("%s", err.msg);
    /* Two model objects (one instance each, sharing one mesh) and the plane. */
    assert_int_equal(scene.object_count, 3);
    assert_int_equal(scene.mesh_count, 2);
    assert_int_equal(scene.objects[0].mesh, scene.objects[1].mesh);
    /* (1,0,0) -> (3, -3, 2) by the nodes, then translated by (10, 0, 0). */
    vec3 w = xyz(mat4_mul_vec4(scene.objects[0].model, vec4(1, 0, 0, 1)));
    assert_near(w.x, 13.0f, 1e-5f);
    assert_near(w.y, -3.0f, 1e-5f);
    assert_string_equal(scene.materials[scene.objects[1].material].name, "red");
    assert_near(scene.materials[scene.objects[0].material].kd.x, 0.8f, 1e-6f); /* the base colour */
    sl_scene_free(&scene);

    /* Parsed without meshes, a model object is one object with a model source. */
    assert_true(sl_scene_parse(json, strlen(json), "m.json", "", false, &scene, &err));
    assert_int_equal(scene.mesh_sources[scene.objects[0].mesh].kind, SL_MESH_MODEL);
    sl_scene_free(&scene);
    const char *both = "{\"objects\": [{\"model\": \"a.glb\", \"mesh\": \"b.obj\"}]}";
    assert_false(sl_scene_parse(both, strlen(both), "m.json", "", false, &scene, &err));
    assert_msg_contains(err, "more than one of");
    /* A bad model inside a scene names the scene, the object and the file. */
    const char *bad = "{\"objects\": [{\"model\": \"missing.glb\"}]}";
    test_write_bytes(test_tmpfile("bad-scene.json"), bad, strlen(bad));
    assert_false(sl_scene_load(test_tmpfile("bad-scene.json"), &scene, &err));
    assert_msg_contains(err, "objects[0].model: ");
    assert_msg_contains(err, "missing.glb");
}

static void test_bad_files(void **state)
{
    (void)state;
    unsigned char bin[BIN_SIZE];
    size_t png_size;
    unsigned char *png = png_bytes(&png_size);
    test_write_bytes(test_tmpfile("tex.png"), png, png_size);
    free(png);

    /* A missing .bin. */
    triangle_bin(bin, 0.0f, 2);
    write_gltf_files("nobin", NODES, bin);
    remove(test_tmpfile("nobin.bin"));
    load_fails(test_tmpfile("nobin.gltf"), "nobin.bin");

    /* A missing image. */
    write_gltf_files("noimage", NODES, bin);
    char text[4096], buffer[128];
    snprintf(buffer, sizeof buffer, "{\"uri\": \"noimage.bin\", \"byteLength\": %d}", BIN_SIZE);
    gltf_text(text, sizeof text, NODES, buffer, "[{\"uri\": \"gone.png\"}]");
    test_write_bytes(test_tmpfile("noimage.gltf"), text, strlen(text));
    load_fails(test_tmpfile("noimage.gltf"), "gone.png");

    /* Indices out of range: index 7 of 3 vertices. */
    triangle_bin(bin, 0.0f, 7);
    write_gltf_files("index", NODES, bin);
    /* assimp's glTF importer drops the face (with a log line nobody sees) and its validation
     * then finds the mesh empty: that is the message the user gets. */
    load_fails(test_tmpfile("index.gltf"), "has no faces");

    /* NaN and Inf positions. */
    triangle_bin(bin, NAN, 2);
    write_gltf_files("nan", NODES, bin);
    load_fails(test_tmpfile("nan.gltf"), "nan.gltf");
    triangle_bin(bin, INFINITY, 2);
    write_gltf_files("inf", NODES, bin);
    load_fails(test_tmpfile("inf.gltf"), "inf.gltf");

    /* Recursive nodes: 0 -> 1 -> 0. */
    triangle_bin(bin, 0.0f, 2);
    write_gltf_files("cycle", "[{\"children\": [1]}, {\"children\": [0], \"mesh\": 0}]", bin);
    load_fails(test_tmpfile("cycle.gltf"), "recursive");
    write_gltf_files("self", "[{\"children\": [0], \"mesh\": 0}]", bin);
    load_fails(test_tmpfile("self.gltf"), "recursive");

    /* Wrong JSON types. */
    write_gltf_files("types", "[{\"scale\": \"big\", \"mesh\": 0}]", bin);
    load_fails(test_tmpfile("types.gltf"), "nodes[0].scale: expected an array of 3 numbers");
    write_gltf_files("types2", "{\"mesh\": 0}", bin);
    load_fails(test_tmpfile("types2.gltf"), "nodes: expected an array");

    /* A textureInfo without "index" (assimp 5.2 crashes on it: gltf_check.c refuses it first). */
    write_gltf_files("noindex", NODES, bin);
    char noindex[4096];
    snprintf(buffer, sizeof buffer, "{\"uri\": \"noindex.bin\", \"byteLength\": %d}", BIN_SIZE);
    gltf_text(noindex, sizeof noindex, NODES, buffer, "[{\"uri\": \"tex.png\"}]");
    char *at = strstr(noindex, "\"baseColorTexture\": {\"index\"");
    assert_non_null(at);
    memcpy(at + 22, "inaex", 5);
    test_write_bytes(test_tmpfile("noindex.gltf"), noindex, strlen(noindex));
    load_fails(test_tmpfile("noindex.gltf"), "materials[0].pbrMetallicRoughness.baseColorTexture.index: expected a texture index");

    /* An unknown format, and a file that is not what its extension says. */
    test_write_bytes(test_tmpfile("model.xyz"), "hello", 5);
    load_fails(test_tmpfile("model.xyz"), "unknown model format");
    test_write_bytes(test_tmpfile("junk.glb"), "hello world, not a glb", 22);
    load_fails(test_tmpfile("junk.glb"), "no \"glTF\" magic");
    test_write_bytes(test_tmpfile("junk.ply"), "hello world, not a ply", 22);
    load_fails(test_tmpfile("junk.ply"), "Invalid .ply file");
    /* Not there at all. */
    load_fails(test_tmpfile("absent.gltf"), "absent.gltf");
}

/* ---- materials drawn: what arrives in the G-buffer ---- */

/* A 2x2 RGBA PNG, bytes written out (the project's PNG writer takes 1 or 3 channels): texel
 * (0,0) sRGB (255, 128, 0) opaque; (1,0) and (1,1) grey 200 opaque; (0,1) grey 200 with
 * alpha 51 (0.2). Made with zlib by hand; 8-bit RGBA, no filter. */
static const unsigned char RGBA_PNG[80] = {
    0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48, 0x44, 0x52,
    0x00, 0x00, 0x00, 0x02, 0x00, 0x00, 0x00, 0x02, 0x08, 0x06, 0x00, 0x00, 0x00, 0x72, 0xb6, 0x0d,
    0x24, 0x00, 0x00, 0x00, 0x17, 0x49, 0x44, 0x41, 0x54, 0x78, 0xda, 0x63, 0xf8, 0xdf, 0xc0, 0xf0,
    0xff, 0xc4, 0x89, 0x13, 0xff, 0x19, 0x80, 0x84, 0x31, 0x88, 0x01, 0x00, 0x66, 0x77, 0x0b, 0xb8,
    0x4c, 0x10, 0x21, 0x10, 0x00, 0x00, 0x00, 0x00, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82};

/* The G-buffer texel at the centre of a 33x33 frame of `scene` looking from `eye` at `at`
 * along +Y (the test models face -Y), through the textured G-buffer program. */
static sl_gbuffer_texel centre_texel(sl_scene *scene, vec3 at)
{
    sl_error err = {0};
    scene->camera = (sl_camera){.eye = sub3(at, vec3(0, 5, 0)), .target = at, .up = vec3(0, 0, 1),
                                .fovy_deg = 30, .znear = 0.1f, .zfar = 100};
    sl_scene_textures tex;
    sl_raster *r = sl_raster_create(&(sl_raster_desc){.threads = 1}, &err);
    sl_gbuffer gb = {0};
    if (!r || !sl_scene_textures_load(scene, 0, &tex, &err) || !sl_gbuffer_resize(&gb, 33, 33, &err) ||
        !sl_raster_scene_textured(r, scene, &tex, &scene->camera, &gb, &err))
        fail_msg("%s", err.msg);
    sl_gbuffer_texel t = *sl_gbuffer_at(&gb, 16, 16);
    sl_gbuffer_free(&gb);
    sl_scene_textures_free(&tex);
    sl_raster_destroy(r);
    return t;
}

/* The glTF triangle under NODES: object (x, y, 0) -> scaled 2, translated (1, 2, 3), Z-up:
 * world (1 + 2x, -3, 2 + 2y). Object (0.1, 0.1) (barycentrics 0.1, 0.1 on vertices 1 and 2)
 * has UV 0.1 (0.25, 0.75) + 0.1 (0, 1) = (0.025, 0.175): texel (0,0). Object (0.1, 0.8) has UV
 * (0.025, 0.875): texel (0,1), alpha 0.2. */
#define AT_OPAQUE vec3(1.2f, -3.0f, 2.2f)
#define AT_CUT vec3(1.2f, -3.0f, 3.6f)

/* What the material `clay` (gltf_text) draws at texel (0,0) (magFilter NEAREST: the texel
 * itself): base = (0.8, 0.4, 0.2) times the sRGB texel (1, srgb(128) = 0.21586, 0); the same image
 * read linear as metallicRoughnessTexture: G = 128/255, B = 0, so metallic = 0.25 * 0 = 0 (a
 * dielectric: Kd = base, Ks = 0.04) and roughness = 0.6 * 128/255; MASK 0.3 cuts the texel of
 * alpha 0.2. */
static void check_clay_drawn(sl_scene *scene)
{
    sl_gbuffer_texel t = centre_texel(scene, AT_OPAQUE);
    assert_true(sl_gbuffer_covered(&t));
    assert_near(t.kd.x, 0.8f, 1e-6f);
    assert_near(t.kd.y, 0.4f * sl_srgb8_to_linear(128), 1e-6f);
    assert_near(t.kd.y, 0.4f * 0.21586f, 1e-5f);
    assert_near(t.kd.z, 0.0f, 1e-7f);
    assert_near(t.ks.x, 0.04f, 1e-7f);
    assert_near(t.ks.y, 0.04f, 1e-7f);
    assert_near(t.ks.z, 0.04f, 1e-7f);
    assert_near(t.alpha, sl_gbuffer_ggx_alpha(0.6f * 128.0f / 255.0f), 1e-6f);
    assert_near(t.normal.y, -1.0f, 1e-5f);
    t = centre_texel(scene, AT_CUT);
    assert_false(sl_gbuffer_covered(&t));
}

static void test_gltf_material_drawn(void **state)
{
    (void)state;
    unsigned char bin[BIN_SIZE];
    triangle_bin(bin, 0.0f, 2);
    write_gltf_files("drawn", NODES, bin);
    test_write_bytes(test_tmpfile("tex.png"), RGBA_PNG, sizeof RGBA_PNG);
    sl_scene scene;
    sl_error err = {0};
    if (!sl_scene_load(test_tmpfile("drawn.gltf"), &scene, &err))
        fail_msg("%s", err.msg);
    /* A textured GGX material whose kd_map names the file, sRGB, with the glTF sampler's clamp
     * (wrapS; wrapT is repeat: differing axes, wrapS wins) and magFilter NEAREST. */
    const sl_material *mat = &scene.materials[scene.objects[0].material];
    assert_int_equal(mat->brdf, SL_BRDF_GGX);
    assert_true(mat->textured);
    assert_true(mat->maps[SL_MAP_KD].set);
    assert_false(mat->maps[SL_MAP_KS].set); /* Ks per texel from the base colour */
    assert_false(mat->maps[SL_MAP_ALPHA].set);
    assert_true(mat->maps[SL_MAP_METALLIC_ROUGHNESS].set);
    /* the file twice: sRGB as base colour, linear as metallic-roughness */
    assert_int_equal(scene.image_count, 2);
    assert_false(scene.images[mat->maps[SL_MAP_METALLIC_ROUGHNESS].image].srgb);
    assert_string_equal(scene.images[mat->maps[SL_MAP_KD].image].path, test_tmpfile("tex.png"));
    assert_true(scene.images[0].srgb);
    assert_null(scene.images[0].bytes);
    assert_int_equal(mat->maps[SL_MAP_KD].wrap, SL_MAP_CLAMP);
    assert_int_equal(mat->maps[SL_MAP_KD].filter, SL_MAP_NEAREST);
    assert_true(mat->masked);
    assert_near(mat->alpha_cutoff, 0.3f, 1e-6f);
    check_clay_drawn(&scene);
    sl_scene_free(&scene);

    /* The same material on a mesh without texture coordinates: drawn with its constants (Kd =
     * 0.6, 0.3, 0.15), not refused by the raster stage, and not cut. */
    char text[4096], buffer[128];
    snprintf(buffer, sizeof buffer, "{\"uri\": \"drawn.bin\", \"byteLength\": %d}", BIN_SIZE);
    gltf_text(text, sizeof text, NODES, buffer, "[{\"uri\": \"tex.png\"}]");
    char *at = strstr(text, ", \"TEXCOORD_0\": 1");
    assert_non_null(at);
    memmove(at, at + 17, strlen(at + 17) + 1);
    test_write_bytes(test_tmpfile("nouv.gltf"), text, strlen(text));
    if (!sl_scene_load(test_tmpfile("nouv.gltf"), &scene, &err))
        fail_msg("%s", err.msg);
    assert_false(scene.materials[scene.objects[0].material].textured);
    sl_gbuffer_texel t = centre_texel(&scene, AT_CUT);
    assert_true(sl_gbuffer_covered(&t));
    assert_near(t.kd.x, 0.6f, 1e-6f);
    assert_near(t.kd.y, 0.3f, 1e-6f);
    assert_near(t.kd.z, 0.15f, 1e-6f);
    sl_scene_free(&scene);
}

static void test_glb_material_drawn(void **state)
{
    (void)state;
    size_t size;
    unsigned char *glb = glb_bytes(&size, RGBA_PNG, sizeof RGBA_PNG);
    test_write_bytes(test_tmpfile("drawn.glb"), glb, size);
    free(glb);
    remove(test_tmpfile("tex.png")); /* nothing on disk: the image is the .glb's */
    sl_scene scene;
    sl_error err = {0};
    if (!sl_scene_load(test_tmpfile("drawn.glb"), &scene, &err))
        fail_msg("%s", err.msg);
    /* One scene image per colour space holding the embedded bytes, named after the model. */
    assert_int_equal(scene.image_count, 2);
    char name[SL_PATH_MAX];
    snprintf(name, sizeof name, "%s#0", test_tmpfile("drawn.glb"));
    assert_string_equal(scene.images[0].path, name);
    assert_int_equal(scene.images[0].size, sizeof RGBA_PNG);
    assert_memory_equal(scene.images[0].bytes, RGBA_PNG, sizeof RGBA_PNG);
    check_clay_drawn(&scene);
    sl_scene_free(&scene);
}

/* A metal (metallic 1, no metallicRoughnessTexture) takes its Ks from the base colour texture too;
 * BLEND is drawn as MASK at 0.5. */
static void test_gltf_metal_blend(void **state)
{
    (void)state;
    unsigned char bin[BIN_SIZE];
    triangle_bin(bin, 0.0f, 2);
    char text[4096], buffer[128];
    snprintf(buffer, sizeof buffer, "{\"uri\": \"metal.bin\", \"byteLength\": %d}", BIN_SIZE);
    gltf_text(text, sizeof text, NODES, buffer, "[{\"uri\": \"tex.png\"}]");
    char *at = strstr(text, "\"metallicFactor\": 0.25");
    assert_non_null(at);
    memcpy(at, "\"metallicFactor\": 1.00", 22);
    /* factors only: without the metallicRoughnessTexture */
    const char *mr = ", \"metallicRoughnessTexture\": {\"index\": 0}";
    at = strstr(text, mr);
    assert_non_null(at);
    memmove(at, at + strlen(mr), strlen(at + strlen(mr)) + 1);
    at = strstr(text, "\"MASK\"");
    memcpy(at, "\"BLEND\"", 7); /* overwrites the comma after "MASK" */
    at += 7;
    memmove(at + 1, at, strlen(at) + 1);
    *at = ',';
    test_write_bytes(test_tmpfile("metal.gltf"), text, strlen(text));
    test_write_bytes(test_tmpfile("metal.bin"), bin, BIN_SIZE);
    test_write_bytes(test_tmpfile("tex.png"), RGBA_PNG, sizeof RGBA_PNG);
    sl_scene scene;
    sl_error err = {0};
    if (!sl_scene_load(test_tmpfile("metal.gltf"), &scene, &err))
        fail_msg("%s", err.msg);
    const sl_material *mat = &scene.materials[scene.objects[0].material];
    assert_true(mat->maps[SL_MAP_KS].set);
    assert_true(mat->masked);
    assert_near(mat->alpha_cutoff, 0.5f, 1e-6f);
    /* Kd = base (1 - 1) = 0; Ks = base * texel = (0.8, 0.4 * 0.21586, 0). */
    sl_gbuffer_texel t = centre_texel(&scene, AT_OPAQUE);
    assert_near(t.kd.x, 0.0f, 1e-7f);
    assert_near(t.ks.x, 0.8f, 1e-6f);
    assert_near(t.ks.y, 0.4f * sl_srgb8_to_linear(128), 1e-6f);
    assert_near(t.ks.z, 0.0f, 1e-7f);
    assert_false(sl_gbuffer_covered((t = centre_texel(&scene, AT_CUT), &t)));
    sl_scene_free(&scene);
}

/* OBJ + MTL: the Phong set with map_Kd (sRGB) and map_Ns (linear, scaling Ns). The quad
 * (0..1)^2 at z = 0 turns Z-up into x, z in 0..1 at y = 0 facing -Y; OBJ point (0.25, 0.75) has
 * vt (0.25, 0.75), glTF's (0.25, 0.25): texel (0,0); point (0.75, 0.25) has glTF (0.75, 0.75):
 * texel (1,1), grey 200. */
static void test_obj_mtl_drawn(void **state)
{
    (void)state;
    const char *obj = "mtllib d.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                      "usemtl brass\nf 1/1 2/2 3/3 4/4\n";
    const char *mtl = "newmtl brass\nKd 0.5 0.25 0.125\nKs 0.9 0.8 0.7\nNs 250\nmap_Kd tex.png\nmap_Ns tex.png\n";
    test_write_bytes(test_tmpfile("d.obj"), obj, strlen(obj));
    test_write_bytes(test_tmpfile("d.mtl"), mtl, strlen(mtl));
    test_write_bytes(test_tmpfile("tex.png"), RGBA_PNG, sizeof RGBA_PNG);
    sl_scene scene;
    sl_error err = {0};
    if (!sl_scene_load(test_tmpfile("d.obj"), &scene, &err))
        fail_msg("%s", err.msg);
    const sl_material *mat = &scene.materials[scene.objects[0].material];
    assert_int_equal(mat->brdf, SL_BRDF_PHONG);
    assert_true(mat->maps[SL_MAP_KD].set && mat->maps[SL_MAP_ALPHA].set);
    /* One file, two colour spaces: two scene images. */
    assert_int_equal(scene.image_count, 2);
    assert_true(scene.images[mat->maps[SL_MAP_KD].image].srgb);
    assert_false(scene.images[mat->maps[SL_MAP_ALPHA].image].srgb);
    /* Texel (0,0): kd = (0.5, 0.25 srgb(128), 0), alpha = 250 * 1 (linear 255). MTL gives no
     * filter: trilinear, bilinear between texel centres at this magnification. The points are
     * texel centres, but the pixel centre lands 1e-4 of the quad off them (float rounding in the
     * projection), and a texel step here is 0.5 in kd: tolerance 2e-4. */
    const float tol = 2e-4f;
    sl_gbuffer_texel t = centre_texel(&scene, vec3(0.25f, 0.0f, 0.75f));
    assert_near(t.kd.x, 0.5f, tol);
    assert_near(t.kd.y, 0.25f * sl_srgb8_to_linear(128), tol);
    assert_near(t.kd.z, 0.0f, tol);
    assert_near(t.ks.x, 0.9f, 1e-6f);
    assert_near(t.alpha, 250.0f, 250.0f * tol);
    /* Texel (1,1): kd = 0.5 srgb(200), alpha = 250 * 200 / 255 (map_Ns is linear). */
    t = centre_texel(&scene, vec3(0.75f, 0.0f, 0.25f));
    assert_near(t.kd.x, 0.5f * sl_srgb8_to_linear(200), tol);
    assert_near(t.alpha, 250.0f * 200.0f / 255.0f, 250.0f * tol);
    sl_scene_free(&scene);
}

/* A glTF document of `count` copies of `element` (a printf format that may take the next
 * element's index, for a chain) as the array `key`, the last one `last`, after `head` (more
 * top-level members). */
static void write_repeated(const char *file, const char *head, const char *key, const char *element,
                           const char *last, int count)
{
    size_t cap = strlen(head) + 64 + (size_t)count * (strlen(element) + 24);
    char *text = malloc(cap);
    assert_non_null(text);
    size_t n = (size_t)snprintf(text, cap, "{\"asset\": {\"version\": \"2.0\"}, %s\"%s\": [", head, key);
    for (int i = 0; i < count; i++) {
        n += (size_t)snprintf(text + n, cap - n, i ? "," : "");
        n += (size_t)snprintf(text + n, cap - n, i + 1 < count ? element : last, i + 1);
    }
    n += (size_t)snprintf(text + n, cap - n, "]}");
    test_write_bytes(test_tmpfile(file), text, n);
    free(text);
}

/* The document's sizes and its node graph are checked before the importer runs, in linear time:
 * a deep chain would overflow the importer's recursion, and 200,000 nodes took minutes in a check
 * that counted an array per element. */
static void test_gltf_graph_limits(void **state)
{
    (void)state;
    const char *mesh = "\"meshes\": [{\"primitives\": [{\"attributes\": {}}]}], ";
    /* A chain: node i's child is node i + 1, the last holds the mesh. */
    write_repeated("chain.gltf", mesh, "nodes", "{\"children\": [%d]}", "{\"mesh\": 0}", 20000);
    load_fails(test_tmpfile("chain.gltf"), "nodes nested deeper than 256 levels");
    write_repeated("chain5k.gltf", mesh, "nodes", "{\"children\": [%d]}", "{\"mesh\": 0}", 5000);
    load_fails(test_tmpfile("chain5k.gltf"), "nodes nested deeper than 256 levels");
    /* Wide: 200,000 empty nodes, 100,000 meshes: over the caps, refused before any element. */
    write_repeated("wide.gltf", "", "nodes", "{}", "{}", 200000);
    load_fails(test_tmpfile("wide.gltf"), "200000 nodes (softlight reads at most 65536)");
    write_repeated("meshes.gltf", "", "meshes", "{\"primitives\": []}", "{\"primitives\": []}", 100000);
    load_fails(test_tmpfile("meshes.gltf"), "100000 meshes (softlight reads at most 4096)");
    /* 2,000 nodes each placing a mesh of 40 primitives: 80,000 instances. */
    char prims[2048] = "\"meshes\": [{\"primitives\": [";
    for (int i = 0; i < 40; i++)
        strcat(prims, i ? ", {\"attributes\": {}}" : "{\"attributes\": {}}");
    strcat(prims, "]}], ");
    write_repeated("instances.gltf", prims, "nodes", "{\"mesh\": 0}", "{\"mesh\": 0}", 2000);
    load_fails(test_tmpfile("instances.gltf"), "80000 mesh instances (softlight draws at most 65536)");
    /* Two parents: not a tree. */
    write_repeated("dag.gltf", mesh, "nodes", "{\"children\": [2]}", "{\"mesh\": 0}", 3);
    load_fails(test_tmpfile("dag.gltf"), "nodes[2] has two parents, nodes[0] and nodes[1]");
    /* A required extension softlight does not implement, and a glTF 1.0 file. */
    const char *draco = "{\"asset\": {\"version\": \"2.0\"}, \"extensionsRequired\": [\"KHR_draco_mesh_compression\"]}";
    test_write_bytes(test_tmpfile("draco.gltf"), draco, strlen(draco));
    load_fails(test_tmpfile("draco.gltf"), "requires the glTF extension KHR_draco_mesh_compression");
    const char *v1 = "{\"asset\": {\"version\": \"1.0\"}, \"scenes\": {\"s\": {\"nodes\": []}}}";
    test_write_bytes(test_tmpfile("v1.gltf"), v1, strlen(v1));
    load_fails(test_tmpfile("v1.gltf"), "glTF version \"1.0\" (softlight reads glTF 2.0)");
    /* glTF 1.0 as collada2gltf wrote it: the version a number; or no version and 1.0's layout. */
    const char *v1n = "{\"asset\": {\"version\": 1}, \"scenes\": {\"s\": {\"nodes\": []}}}";
    test_write_bytes(test_tmpfile("v1n.gltf"), v1n, strlen(v1n));
    load_fails(test_tmpfile("v1n.gltf"), "glTF version 1 (softlight reads glTF 2.0)");
    const char *v1l = "{\"asset\": {}, \"nodes\": {\"n\": {}}}";
    test_write_bytes(test_tmpfile("v1l.gltf"), v1l, strlen(v1l));
    load_fails(test_tmpfile("v1l.gltf"), "\"nodes\" is an object keyed by id: glTF 1.0's layout");
}

/* Texture references as other tools write them find the file beside the model: Windows
 * separators, Blender's "//", another case, an absolute path of another machine. */
static void test_texture_path_forms(void **state)
{
    (void)state;
    char dir[SL_PATH_MAX], got[SL_PATH_MAX], want[2 * SL_PATH_MAX];
    snprintf(dir, sizeof dir, "%s", test_tmpfile(""));
    mkdir(test_tmpfile("Maps"), 0755);
    test_write_bytes(test_tmpfile("Wood.png"), "x", 1);
    test_write_bytes(test_tmpfile("Maps/bark.JPG"), "x", 1);
    static const struct {
        const char *ref, *file;
    } found[] = {
        {"Wood.png", "Wood.png"},          {".\\Wood.png", "Wood.png"},          {"//Wood.png", "Wood.png"},
        {"WOOD.PNG", "Wood.png"},          {"Q:/art/textures/wood.png", "Wood.png"},
        {"/home/someone/wood.png", "Wood.png"}, {"maps\\BARK.jpg", "Maps/bark.JPG"},
        {"./Maps/bark.JPG", "Maps/bark.JPG"}, {"C:\\x\\y\\wood.PNG", "Wood.png"},
    };
    for (size_t i = 0; i < sizeof found / sizeof found[0]; i++) {
        snprintf(want, sizeof want, "%s%s", dir, found[i].file);
        if (!sl_scene_texture_path_resolve(dir, found[i].ref, got) || strcmp(got, want) != 0)
            fail_msg("\"%s\": expected %s", found[i].ref, want);
    }
    /* bark.JPG is in Maps/, not beside the model: a bare name does not search folders. */
    static const char *const missing[] = {"bark.jpg", "gone.png", "Maps", "Q:", "//", "..", ""};
    for (size_t i = 0; i < sizeof missing / sizeof missing[0]; i++)
        if (sl_scene_texture_path_resolve(dir, missing[i], got))
            fail_msg("\"%s\": expected no file, got %s", missing[i], got);
    /* Through a model: an OBJ whose material names ".\WOOD.PNG". */
    size_t png_size;
    unsigned char *png = png_bytes(&png_size);
    test_write_bytes(test_tmpfile("Wood.png"), png, png_size);
    free(png);
    const char *obj = "mtllib win.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nusemtl m\nf 1/1 2/2 3/3\n";
    const char *mtl = "newmtl m\nKd 1 1 1\nmap_Kd .\\WOOD.PNG\n";
    test_write_bytes(test_tmpfile("win.obj"), obj, strlen(obj));
    test_write_bytes(test_tmpfile("win.mtl"), mtl, strlen(mtl));
    sl_model m;
    load_ok(test_tmpfile("win.obj"), &m);
    assert_int_equal(m.image_count, 1);
    assert_string_equal(m.images[0].path, test_tmpfile("Wood.png"));
    sl_model_free(&m);
}

/* Index data the importer would take in part: an index out of range drops its triangle (the
 * rest would be drawn without a word), a triangle list of 4 indices, a .glb longer than its
 * header says. */
static void test_gltf_index_counts(void **state)
{
    (void)state;
    /* Two triangles over 3 vertices: (0, 1, 2) and (0, 2, 7). */
    const char *doc =
        "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0}],"
        "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":1}]}],"
        "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\",\"min\":[0,0,0],"
        "\"max\":[1,1,0]},{\"bufferView\":1,\"componentType\":5123,\"count\":%d,\"type\":\"SCALAR\"}],"
        "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":36},{\"buffer\":0,\"byteOffset\":36,"
        "\"byteLength\":%d}],\"buffers\":[{\"byteLength\":48,\"uri\":\"data:application/octet-stream;base64,"
        "AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAABAAIAAAACAAcA\"}]}";
    char text[2048];
    int n = snprintf(text, sizeof text, doc, 6, 12);
    test_write_bytes(test_tmpfile("range.gltf"), text, (size_t)n);
    load_fails(test_tmpfile("range.gltf"), "1 of its 2 triangles have an index out of range");
    n = snprintf(text, sizeof text, doc, 4, 8);
    test_write_bytes(test_tmpfile("four.gltf"), text, (size_t)n);
    load_fails(test_tmpfile("four.gltf"), "meshes[0].primitives[0]: 4 indices, not a multiple of 3");
    /* The first triangle alone loads. */
    n = snprintf(text, sizeof text, doc, 3, 6);
    test_write_bytes(test_tmpfile("one.gltf"), text, (size_t)n);
    sl_model m;
    load_ok(test_tmpfile("one.gltf"), &m);
    assert_int_equal(m.meshes[0].mesh.triangle_count, 1);
    sl_model_free(&m);
    /* A .glb with 8 bytes after the length its header gives. */
    unsigned char glb[40] = "glTF\2\0\0\0";
    glb[8] = 32; /* length 32, file 40 */
    memcpy(glb + 12, "\x08\0\0\0JSON{}      ", 16);
    test_write_bytes(test_tmpfile("long.glb"), glb, sizeof glb);
    load_fails(test_tmpfile("long.glb"), "damaged .glb: its header says 32 bytes, the file has 40");
}

/* Values that would give an empty picture or a message naming nothing: a number past the
 * double range, a count past int, a node matrix of zeros or of 1e38, a file with no extension. */
static void test_gltf_values(void **state)
{
    (void)state;
    const char *doc =
        "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0%s}],"
        "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0}}]}],"
        "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":%s,\"type\":\"VEC3\",\"min\":[0,0,0],"
        "\"max\":[1,1,0]}],\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":36}],"
        "\"buffers\":[{\"byteLength\":36,\"uri\":\"data:application/octet-stream;base64,"
        "AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA\"}]}";
    static const struct {
        const char *file, *node, *count, *want;
    } cases[] = {
        {"inf.gltf", ",\"translation\":[1e999,0,0]", "3", "nodes[0].translation[0]: a number out of range"},
        {"count.gltf", "", "2147483648", "accessors[0].count: 2147483648 is too large (at most 2147483647)"},
        {"zero.gltf", ",\"matrix\":[0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0]", "3",
         "every node that places a mesh scales it to nothing"},
        {"huge.gltf", ",\"scale\":[1e38,1e38,1e38]", "3", "transform out of range (an element of 1e+38"},
    };
    char text[2048];
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        int n = snprintf(text, sizeof text, doc, cases[i].node, cases[i].count);
        test_write_bytes(test_tmpfile(cases[i].file), text, (size_t)n);
        load_fails(test_tmpfile(cases[i].file), cases[i].want);
    }
    int n = snprintf(text, sizeof text, doc, "", "3");
    test_write_bytes(test_tmpfile("tri.gltf"), text, (size_t)n);
    sl_model m;
    load_ok(test_tmpfile("tri.gltf"), &m);
    sl_model_free(&m);
    test_write_bytes(test_tmpfile("noext"), text, (size_t)n);
    load_fails(test_tmpfile("noext"), "no file extension");
}

/* KHR_texture_transform: the base colour map reads uv * scale + offset, as glTF writes them (in
 * its V-down texture space, which softlight keeps), also when the file requires the extension; a
 * rotation, which a map's scale and offset cannot express, is refused. */
static void test_gltf_texture_transform(void **state)
{
    (void)state;
    unsigned char bin[BIN_SIZE];
    triangle_bin(bin, 0.0f, 2);
    test_write_bytes(test_tmpfile("tex.png"), RGBA_PNG, sizeof RGBA_PNG);
    static const struct {
        const char *file, *transform;
        bool ok;
    } cases[] = {
        {"uvt.gltf", "\"offset\": [0.25, 0.5], \"scale\": [2, 3]", true},
        {"uvrot.gltf", "\"offset\": [0.25, 0.5], \"scale\": [2, 3], \"rotation\": 0.5", false},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char name[32], text[4096], buffer[128], edited[4400];
        snprintf(name, sizeof name, "%.*s", (int)(strlen(cases[i].file) - 5), cases[i].file);
        write_gltf_files(name, NODES, bin);
        snprintf(buffer, sizeof buffer, "{\"uri\": \"%s.bin\", \"byteLength\": %d}", name, BIN_SIZE);
        gltf_text(text, sizeof text, NODES, buffer, "[{\"uri\": \"tex.png\"}]");
        const char *at = strstr(text, "\"baseColorTexture\": {\"index\": 0}");
        assert_non_null(at);
        int n = snprintf(edited, sizeof edited,
                         "%.*s\"baseColorTexture\": {\"index\": 0, \"extensions\": {\"KHR_texture_transform\": {%s}}}%s",
                         (int)(at - text), text, cases[i].transform, at + strlen("\"baseColorTexture\": {\"index\": 0}"));
        /* the extension required, at the top level */
        char *open = strchr(edited, '{');
        char final[4600];
        n = snprintf(final, sizeof final, "{\"extensionsUsed\": [\"KHR_texture_transform\"], "
                     "\"extensionsRequired\": [\"KHR_texture_transform\"], %s", open + 1);
        test_write_bytes(test_tmpfile(cases[i].file), final, (size_t)n);
        if (!cases[i].ok) {
            load_fails(test_tmpfile(cases[i].file), "a texture transform with a rotation (0.5 rad)");
            continue;
        }
        sl_scene scene;
        sl_error err = {0};
        if (!sl_scene_load(test_tmpfile(cases[i].file), &scene, &err))
            fail_msg("%s", err.msg);
        const sl_material *mat = &scene.materials[scene.objects[0].material];
        assert_true(mat->maps[SL_MAP_KD].set);
        assert_near(mat->maps[SL_MAP_KD].uv_scale.x, 2.0f, 1e-6f);
        assert_near(mat->maps[SL_MAP_KD].uv_scale.y, 3.0f, 1e-6f);
        assert_near(mat->maps[SL_MAP_KD].uv_offset.x, 0.25f, 1e-6f);
        assert_near(mat->maps[SL_MAP_KD].uv_offset.y, 0.5f, 1e-6f);
        /* the metallic-roughness map has no transform */
        assert_near(mat->maps[SL_MAP_METALLIC_ROUGHNESS].uv_scale.y, 1.0f, 0.0f);
        assert_near(mat->maps[SL_MAP_METALLIC_ROUGHNESS].uv_offset.y, 0.0f, 0.0f);
        sl_scene_free(&scene);
    }
}

/* A missing texture whose path is longer than any message buffer: one bounded line naming the
 * model and the start of the path, never a write past the excerpt's buffer (ASan sees one). */
static void test_missing_texture_long_path(void **state)
{
    (void)state;
    char name[192];
    memset(name, 'x', sizeof name - 5);
    memcpy(name + sizeof name - 5, ".png", 5);
    const char *obj = "mtllib long.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nusemtl m\nf 1 2 3\n";
    char mtl[512];
    snprintf(mtl, sizeof mtl, "newmtl m\nKd 0.5 0.5 0.5\nmap_Kd %s\n", name);
    test_write_bytes(test_tmpfile("long.obj"), obj, strlen(obj));
    test_write_bytes(test_tmpfile("long.mtl"), mtl, strlen(mtl));
    load_fails(test_tmpfile("long.obj"), "xxxxxxxx");
    sl_model m;
    sl_error err = {0};
    assert_false(sl_model_load(test_tmpfile("long.obj"), &m, &err));
    assert_non_null(strstr(err.msg, "..."));
}

/* SL_MISSING_TEXTURES_SKIP: the model loads (through the import's child), the missing texture is
 * one warning line naming model, material and file, the slot has no image and the factors stay;
 * a texture named by two materials' slots warns once per material. Many missing textures: the
 * lines that do not fit are counted. */
static void test_missing_texture_skip(void **state)
{
    (void)state;
    const char *obj = "mtllib skip.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\n"
                      "usemtl m\nf 1/1 2/2 3/3\nusemtl n\nf 1/1 3/3 4/1\n";
    const char *mtl = "newmtl m\nKd 0.5 0.25 0.125\nmap_Kd gone.png\nnewmtl n\nKd 1 1 1\nmap_Kd gone.png\n";
    test_write_bytes(test_tmpfile("skip.obj"), obj, strlen(obj));
    test_write_bytes(test_tmpfile("skip.mtl"), mtl, strlen(mtl));
    load_fails(test_tmpfile("skip.obj"), "texture \"gone.png\" not found");
    sl_model m;
    sl_error err = {0};
    if (!sl_model_load_with(test_tmpfile("skip.obj"), SL_MISSING_TEXTURES_SKIP, &m, &err)) {
        print_error("unexpected error: %s\n", err.msg);
        fail();
    }
    assert_int_equal(m.image_count, 0);
    int lines = 0;
    for (const char *c = m.warnings; *c; c++)
        lines += *c == '\n';
    assert_int_equal(lines, 2);
    assert_non_null(strstr(m.warnings, "softlight: warning: "));
    assert_non_null(strstr(m.warnings, "skip.obj: material \"m\": texture \"gone.png\" not found"));
    assert_non_null(strstr(m.warnings, "skip.obj: material \"n\": texture \"gone.png\" not found"));
    assert_int_equal(m.warnings_left_out, 0);
    bool kd = false;
    for (int i = 0; i < m.material_count; i++) {
        assert_int_equal(m.materials[i].base_color_tex.image, -1);
        kd = kd || (m.materials[i].kd.x == 0.5f && m.materials[i].kd.z == 0.125f);
    }
    assert_true(kd);
    sl_model_free(&m);

    /* 40 materials, each with its own missing texture: what fits is listed, the rest counted. */
    char big_obj[4096], big_mtl[4096];
    int no = snprintf(big_obj, sizeof big_obj, "mtllib many.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\n");
    int nm = 0;
    for (int i = 0; i < 40; i++) {
        no += snprintf(big_obj + no, sizeof big_obj - (size_t)no, "usemtl m%d\nf 1/1 2/1 3/1\n", i);
        nm += snprintf(big_mtl + nm, sizeof big_mtl - (size_t)nm, "newmtl m%d\nmap_Kd gone%d.png\n", i, i);
    }
    test_write_bytes(test_tmpfile("many.obj"), big_obj, (size_t)no);
    test_write_bytes(test_tmpfile("many.mtl"), big_mtl, (size_t)nm);
    assert_true(sl_model_load_with(test_tmpfile("many.obj"), SL_MISSING_TEXTURES_SKIP, &m, &err));
    lines = 0;
    for (const char *c = m.warnings; *c; c++)
        lines += *c == '\n';
    assert_true(lines > 0);
    assert_int_equal(lines + m.warnings_left_out, 40);
    sl_model_free(&m);
}

/* The excerpt never writes more than its buffer holds, whatever `max` says. */
static void test_error_excerpt_bounds(void **state)
{
    (void)state;
    char big[300];
    memset(big, 'a', sizeof big - 1);
    big[sizeof big - 1] = '\0';
    char out[16];
    memset(out, '#', sizeof out);
    sl_error_excerpt(big, 200, out, 12);
    assert_string_equal(out, "aaaaaaaa...");
    assert_int_equal(out[12], '#');
    sl_error_excerpt("ab\x1b", 200, out, sizeof out);
    assert_string_equal(out, "ab?");
    sl_error_excerpt("abc", 200, out, 3);
    assert_string_equal(out, "");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_gltf_with_bin_and_png),
        cmocka_unit_test(test_glb_embedded_image),
        cmocka_unit_test(test_obj_mtl),
        cmocka_unit_test(test_gltf_camera),
        cmocka_unit_test(test_ase_lws_camera),
        cmocka_unit_test(test_scene_model_object),
        cmocka_unit_test(test_bad_files),
        cmocka_unit_test(test_gltf_material_drawn),
        cmocka_unit_test(test_glb_material_drawn),
        cmocka_unit_test(test_gltf_metal_blend),
        cmocka_unit_test(test_obj_mtl_drawn),
        cmocka_unit_test(test_missing_texture_long_path),
        cmocka_unit_test(test_missing_texture_skip),
        cmocka_unit_test(test_gltf_graph_limits),
        cmocka_unit_test(test_gltf_index_counts),
        cmocka_unit_test(test_gltf_values),
        cmocka_unit_test(test_gltf_texture_transform),
        cmocka_unit_test(test_texture_path_forms),
        cmocka_unit_test(test_error_excerpt_bounds),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

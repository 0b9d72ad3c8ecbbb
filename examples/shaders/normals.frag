#version 330 core
// normals.frag - the GLSL twin of normals.c: the shading normal (after facing_normal) as colour,
// N * 0.5 + 0.5, and mid grey where nothing was drawn. Run it with OpenGL:
//   softlight-gl render scenes/bunny.json --lighting examples/shaders/normals.frag -o normals-gl.png
// and check it against its C twin:
//   softlight check scenes/bunny.json --lighting examples/shaders/normals.c --glsl examples/shaders/normals.frag
// Compiled after shaders/lighting.frag (its main renamed), so its uniforms and functions are here.

void main()
{
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    if (texelFetch(uDepth, pixel, 0).r >= 1.0) {
        fragColor = vec4(vec3(0.5), 1.0);
        return;
    }
    vec3 P = texelFetch(uPosition, pixel, 0).xyz;
    vec3 V = normalize(uEye - P);
    vec3 N = facing_normal(texelFetch(uNormal, pixel, 0).xyz, V);
    fragColor = vec4(N * 0.5 + 0.5, 1.0);
}

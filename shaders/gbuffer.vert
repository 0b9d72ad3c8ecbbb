// gbuffer.vert - the G-buffer pass's vertex shader (GLSL twin of sl_gbuffer_vert in
// src/raster/gbuffer_shader.c): object space -> world space (kept for lighting) -> clip space.
// The normal goes through the normal matrix transpose(inverse(mat3(uModel))), computed once per
// object on the CPU, and is normalised per fragment, after interpolation.
#version 330 core

layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aNormal;

uniform mat4 uModel;
uniform mat4 uViewProj;
uniform mat3 uNormalMatrix;

out vec3 vWorldPos;
out vec3 vNormal;

void main()
{
    vec4 world = uModel * vec4(aPosition, 1.0);
    vWorldPos = world.xyz;
    vNormal = uNormalMatrix * aNormal;
    gl_Position = uViewProj * world;
}

#version 330 core
// shadow_depth.vert - the shadow maps' depth-only pass (GLSL twin of shadow_vert in
// src/shadow/shadow.c): object space to a map's clip space through one matrix per object, the
// map's view-projection times the object's model, multiplied on the CPU as shadow.c does.

layout(location = 0) in vec3 aPosition;

uniform mat4 uModelViewProj;

void main()
{
    gl_Position = uModelViewProj * vec4(aPosition, 1.0);
}

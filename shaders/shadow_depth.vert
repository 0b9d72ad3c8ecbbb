#version 330 core
// shadow_depth.vert - the shadow maps' depth-only pass (GLSL twin of shadow_vert and masked_vert in
// src/shadow/shadow.c): object space to a map's clip space through one matrix per object, the
// map's view-projection times the object's model, multiplied on the CPU as shadow.c does; the
// texture coordinate for a masked caster's discard ((0, 0) for a mesh without: the attribute's
// default, as softlight's vertex input has it).

layout(location = 0) in vec3 aPosition;
layout(location = 2) in vec2 aTexCoord;

uniform mat4 uModelViewProj;

out vec2 vTexCoord;

void main()
{
    vTexCoord = aTexCoord;
    gl_Position = uModelViewProj * vec4(aPosition, 1.0);
}

// gbuffer_textured.vert - the textured G-buffer pass's vertex shader (GLSL twin of
// sl_gbuffer_tex_vert in src/raster/gbuffer_textured.c): gbuffer.vert plus the texture
// coordinate and the tangent. The tangent is a direction on the surface: it goes through
// mat3(uModel) (uModel3), not the normal matrix; its handedness w passes through.
#version 330 core

layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in vec2 aTexCoord;
layout(location = 3) in vec4 aTangent;

uniform mat4 uModel;
uniform mat4 uViewProj;
uniform mat3 uNormalMatrix;
uniform mat3 uModel3;

out vec3 vWorldPos;
out vec3 vNormal;
out vec2 vTexCoord;
out vec4 vTangent;

void main()
{
    vec4 world = uModel * vec4(aPosition, 1.0);
    vWorldPos = world.xyz;
    vNormal = uNormalMatrix * aNormal;
    vTexCoord = aTexCoord;
    vTangent = vec4(uModel3 * aTangent.xyz, aTangent.w);
    gl_Position = uViewProj * world;
}

#version 450
// Hemicube vertex stage, layered path: instance = hemicube * 5 + face,
// written to gl_Layer (shaderOutputLayer).
#extension GL_GOOGLE_include_directive : require
#extension GL_ARB_shader_viewport_layer_array : require
#include "hemicube_vert.glsl"

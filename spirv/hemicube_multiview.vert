#version 450
// Hemicube vertex stage, multiview path: gl_ViewIndex picks the face.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_multiview : require
#define HEMICUBE_MULTIVIEW 1
#include "hemicube_vert.glsl"

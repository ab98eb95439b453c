#version 450
// Overlay, fragment stage (src/passes/overlay.c): the vertex colour, blended
// over the image by its alpha (the pipeline's blend state).
layout(location = 0) in vec4 v_color;
layout(location = 0) out vec4 out_color;

void main()
{
    out_color = v_color;
}

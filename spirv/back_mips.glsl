// Where the back hemicubes' mip levels lie (spirv/back_mips.comp writes
// them, spirv/cross_reconstruct.comp reads them; issue 16.2, thesis 6.2).
// Level k >= 1 of a face of side res is (res >> k)^2 texels, each the mean
// of the 2^k x 2^k texels of the face it covers; res is divisible by 2^k
// for every level made (src/passes/back_mips.c), so the sizes are exact.
// Per layer (patch p, face f: layer 5p + f) levels 1, 2, ... follow each
// other.
#ifndef XRAD_BACK_MIPS_GLSL
#define XRAD_BACK_MIPS_GLSL

// The first texel of level k >= 1 within its layer: the sum of (res >> j)^2
// for j in [1, k), that is (res^2 - (res >> (k - 1))^2) / 3.
uint back_mip_first(uint res, uint k)
{
    uint top = res >> (k - 1u);
    return (res * res - top * top) / 3u;
}

// Texels of one layer's levels 1..levels.
uint back_mip_layer_texels(uint res, uint levels)
{
    return back_mip_first(res, levels + 1u);
}

#endif

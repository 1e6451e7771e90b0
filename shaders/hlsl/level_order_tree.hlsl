// level_order_tree.hlsl: the HLSL twin of ../glsl/level_order_tree.glsl, for DXR and other HLSL
// users. The GLSL file is written in the subset GLSL and HLSL share; this
// file includes it with HLSL's names for the intrinsics whose names differ
// (micromap_hlsl.hlsl). Contract, buffers (the MMI_* accessor macros, e.g.
// over StructuredBuffer<uint> with GetDimensions for the lengths) and
// return values: as in the GLSL file's header.
//
// Compile with DXC, or with glslang's HLSL front end:
//   glslangValidator -V -D -S comp -e main -Ishaders/hlsl your.hlsl
#include "micromap_hlsl.hlsl"
#include "../glsl/level_order_tree.glsl"

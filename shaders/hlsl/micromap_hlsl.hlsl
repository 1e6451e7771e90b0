// micromap_hlsl.hlsl: what the shared sources in ../glsl need under HLSL:
// HLSL's names of the intrinsics whose GLSL names differ. Included by every
// twin in this folder; defines nothing else.
#ifndef MICROMAP_HLSL_HLSL
#define MICROMAP_HLSL_HLSL
#define bitCount countbits
#endif // MICROMAP_HLSL_HLSL

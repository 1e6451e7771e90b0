/*
 * C oracle for micromap-index: the Vulkan specification's reference
 * BarycentricsToSpaceFillingCurveIndex, compiled as an independent check of
 * the Rust port (src/spec/). Used only by tests and benches. Origin and
 * licence of the reference code: see spec_reference.c (Khronos, CC-BY-4.0).
 */
#ifndef MICROMAP_SPEC_REFERENCE_H
#define MICROMAP_SPEC_REFERENCE_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/*
 * The reference index of barycentrics (u, v) at subdivision `level`.
 *
 * Defined for every u, v and every level: the level is taken modulo 32
 * before the reference's `1u << level`, which C leaves undefined for
 * level >= 32 (x86, ARM and SPIR-V hardware shift by the count modulo 32).
 * The reference only yields valid indices for levels 0..=16.
 */
uint32_t micromap_spec_reference_index(float u, float v, uint32_t level);

#ifdef __cplusplus
}
#endif

#endif /* MICROMAP_SPEC_REFERENCE_H */

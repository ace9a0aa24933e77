// What the host side of the CUDA executor (plain C++, cuda_exec.cpp) and its kernels (compiled once
// by nvcc into the embedded fatbin, cuda_kernels.cu) agree on: the kernel of every op, by name,
// and how the ops travel as kernel parameters.
//
// Each op struct is passed by value to `pbf_op_<name>(uint32_t n, Op op)`, one thread per index.
// The host compiler (g++ on Linux, MinGW on Windows: LP64 against LLP64) and nvcc must lay each op
// out alike; the kernels publish sizeof and alignof of every op in `pbf_op_layout`, which the host
// compares with its own when it loads them (cuda_module.cpp), so a type whose size differs between
// the two compilers is refused at load instead of read wrongly on the device.
#pragma once
#include <cstdint>

#include "../core/bodies.h"
#include "../core/diffuse_ops.h"
#include "../core/material_ops.h"
#include "../core/passes.h"
#include "../core/render_ops.h"
#include "../core/sdf_build.h"
#include "../core/step_ops.h"

namespace pbf {

// Threads per block of the per-particle kernels (their launch bounds are compiled for it).
#ifndef PBF_CUDA_BLOCK
#define PBF_CUDA_BLOCK 256
#endif

// Every op a solver launches through CudaExec::for_each: X(kernel name suffix, op type). A new op
// joins this list, or CudaExec::for_each refuses to compile it.
#define PBF_CUDA_OPS(X)                                     \
    X(CellKey, CellKeyOp)                                   \
    X(CellBegin, CellBeginOp)                               \
    X(Gather, GatherOp)                                     \
    X(CopyMaterials, CopyMaterialsOp)                       \
    X(ResetControl, ResetControlOp)                         \
    X(Convergence, ConvergenceOp)                           \
    X(Density, DensityOp)                                   \
    X(SettleOverlap, SettleOverlapOp)                       \
    X(CopyPositions, CopyPositionsOp)                       \
    X(AdoptSettled, AdoptSettledOp)                         \
    X(Predict, PredictOp)                                   \
    X(Lambda, LambdaOp)                                     \
    X(Delta, DeltaOp)                                       \
    X(VorticityXsph, VorticityXsphOp)                       \
    X(VorticityForce, VorticityForcePass<false>)            \
    X(VorticityForceNormals, VorticityForcePass<true>)      \
    X(LambdaPlain, LambdaPass<true>)                        \
    X(DeltaPlain, DeltaPass<true, false>)                   \
    X(DeltaNoSplit, DeltaPass<false, false>)                \
    X(DeltaBounded, DeltaBounded)                           \
    X(VorticityXsphPlain, VorticityXsphPass<true>)          \
    X(VorticityForcePlain, VorticityForcePass<false, true>) \
    X(EmitBlock, EmitBlockOp)                               \
    X(EmitNozzle, EmitNozzleOp)                             \
    X(CommitEmission, CommitEmissionOp)                     \
    X(Drain, DrainOp)                                       \
    X(CommitDrain, CommitDrainOp)                           \
    X(SurfaceNormal, SurfaceNormalOp)                       \
    X(SurfaceForce, SurfaceForceOp)                         \
    X(ColliderPose, ColliderPoseOp)                         \
    X(ColliderForce, ColliderForceOp)                       \
    X(RenderData, RenderDataOp)                             \
    X(DiffuseNormal, DiffuseNormalOp)                       \
    X(DiffuseSource, DiffuseSourceOp)                       \
    X(DiffuseAdvect, DiffuseAdvectOp)                       \
    X(DiffuseScatter, DiffuseScatterOp)                     \
    X(DiffuseCommit, DiffuseCommitOp)                       \
    X(SdfCorners, SdfCornersOp)                             \
    X(SdfBinCount, SdfBinCountOp)                           \
    X(SdfBinFill, SdfBinFillOp)                             \
    X(SdfBrickBegin, SdfBrickBeginOp)                       \
    X(SdfWindingPart, SdfWindingPartOp)                     \
    X(SdfBrickWinding, SdfBrickWindingOp)                   \
    X(SdfVoxel, SdfVoxelOp)                                 \
    X(SdfBoundary, SdfBoundaryOp)                           \
    X(BeginStep, BeginStepOp)                               \
    X(PublishFeedback, PublishFeedbackOp)

enum CudaOpIndex : uint32_t {
#define PBF_CUDA_OP_INDEX(name, ...) kCudaOp##name,
    PBF_CUDA_OPS(PBF_CUDA_OP_INDEX)
#undef PBF_CUDA_OP_INDEX
        kCudaOpCount
};

// The index of Op's kernel; undefined (a compile error) for an op missing from PBF_CUDA_OPS.
template <class Op>
struct CudaOp;
#define PBF_CUDA_OP_TRAIT(name, ...)                           \
    template <>                                                \
    struct CudaOp<__VA_ARGS__> {                               \
        static constexpr uint32_t index = kCudaOp##name;       \
        static constexpr const char* kernel = "pbf_op_" #name; \
    };
PBF_CUDA_OPS(PBF_CUDA_OP_TRAIT)
#undef PBF_CUDA_OP_TRAIT

// One row of pbf_op_layout per op, in PBF_CUDA_OPS order, then a last row of
// {kCudaOpCount, PBF_CUDA_BLOCK} that says which list and block size the kernels were built for.
struct CudaOpLayout {
    uint32_t size;
    uint32_t align;
};

// The executor's own kernels (scan, sort, reductions, the interop copy): names and tile sizes.
constexpr int kCudaScanBlock = 256;  // threads of a scan or sort block
constexpr int kCudaScanItems = 8;    // keys each thread holds
constexpr int kCudaScanTile = kCudaScanBlock * kCudaScanItems;
constexpr int kCudaRadixBits = 8;  // bits of the key each sort pass orders by
constexpr int kCudaRadixDigits = 1 << kCudaRadixBits;
constexpr int kCudaReduceBlock = 256;

#define PBF_CUDA_UTILITY_KERNELS(X) \
    X(scan_reduce)                  \
    X(scan_spine)                   \
    X(scan_downsweep)               \
    X(radix_upsweep)                \
    X(radix_scan_rows)              \
    X(radix_downsweep)              \
    X(count_keys)                   \
    X(scatter_keys)                 \
    X(order_keys)                   \
    X(reduce_stats)                 \
    X(sum_error)                    \
    X(feedback)                     \
    X(copy_live_u32)                \
    X(copy_live_f4)

}  // namespace pbf

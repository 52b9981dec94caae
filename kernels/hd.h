// Annotation shared by every physics header: the same function compiles for the CPU backend
// (plain C++) and for CUDA kernels (__host__ __device__). Keeping one definition of each formula
// means a CPU/GPU mismatch is a scheduling or precision bug, never a formula bug.
#pragma once

#if defined(__CUDACC__)
#define COREBOX_HD __host__ __device__
#else
#define COREBOX_HD
#endif

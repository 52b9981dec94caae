// GPU tests skip, visibly, where there is no CUDA device (CI); on a GPU machine they compare the
// CUDA backend with the CPU oracle.
#pragma once

#include <gtest/gtest.h>

#include "cpu_backend.h"
#include "cuda_backend.h"

// How many GPUs a multi-GPU test needs: skips, visibly, where fewer are visible.
#define COREBOX_REQUIRE_GPUS(count)                                                                                    \
    do {                                                                                                              \
        const int visible = corebox::cudaDeviceCount();                                                                \
        if (visible < (count))                                                                                        \
            GTEST_SKIP() << "needs " << (count) << " CUDA devices, " << visible << " visible: multi-GPU test skipped"; \
    } while (0)

#define COREBOX_REQUIRE_GPU()                                                                  \
    do {                                                                                       \
        if (corebox::cudaDeviceCount() == 0) GTEST_SKIP() << "no CUDA device: GPU test skipped"; \
    } while (0)

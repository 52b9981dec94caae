// GPU tests skip, visibly, where there is no CUDA device (CI); on a GPU machine they compare the
// CUDA backend with the CPU oracle.
#pragma once

#include <gtest/gtest.h>

#include "cpu_backend.h"
#include "cuda_backend.h"

#define COREBOX_REQUIRE_GPU()                                                                  \
    do {                                                                                       \
        if (corebox::cudaDeviceCount() == 0) GTEST_SKIP() << "no CUDA device: GPU test skipped"; \
    } while (0)

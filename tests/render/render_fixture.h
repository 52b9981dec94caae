// A headless GL context on Mesa's software device (llvmpipe) shared by the render tests, so images
// are the same on every machine, with or without a GPU.
#pragma once

#include <gtest/gtest.h>

#include <memory>

#include "egl_headless_context.h"

namespace corebox::testing {

class RenderTest : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        try {
            s_context = new EglHeadlessContext(HeadlessContextOptions{-1, true});
        } catch (const PlatformError& e) {
            s_error = e.what();
        }
    }
    static void TearDownTestSuite() {
        delete s_context;
        s_context = nullptr;
    }
    void SetUp() override {
        // llvmpipe is installed by scripts/test; without it the render tests cannot run at all,
        // which is a failure, not a skip.
        ASSERT_NE(s_context, nullptr) << "no headless GL context: " << s_error;
    }
    static EglHeadlessContext* s_context;
    static std::string s_error;
};

inline EglHeadlessContext* RenderTest::s_context = nullptr;
inline std::string RenderTest::s_error;

}  // namespace corebox::testing

// A GoogleTest fixture with an OSMesa GL 3.3 core context for the whole suite (no display
// needed). The context is made current again before every test.
#pragma once

#include <memory>

#include <gtest/gtest.h>

#include "render/context.h"

class GlTest : public ::testing::Test {
  protected:
    static void SetUpTestSuite() { context_ = snert::render::create_offscreen_context("osmesa"); }
    static void TearDownTestSuite() { context_.reset(); }
    void SetUp() override { context_->make_current(); }

    static inline std::unique_ptr<snert::render::GlContext> context_;
};

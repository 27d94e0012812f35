// Offscreen contexts: the back ends named on the command line, and the errors when a context
// cannot be made.
#include <string>

#include <gtest/gtest.h>

#include "render/context.h" // glad first
#include "support/expect_error.h"

#include <GL/osmesa.h>

using namespace snert::render;

namespace {
using namespace snert::test;
GLint current_version() {
    GLint major = 0, minor = 0;
    glGetIntegerv(GL_MAJOR_VERSION, &major);
    glGetIntegerv(GL_MINOR_VERSION, &minor);
    return major * 10 + minor;
}
GLint current_profile() {
    GLint mask = 0;
    glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &mask);
    return mask;
}
} // namespace

TEST(Context, UnknownBackendIsAnInvalidArgumentNamingIt) {
    expect_error<std::invalid_argument>([] { create_offscreen_context("vulkan"); },
                                        {"'vulkan'", "osmesa"});
}

TEST(Context, OsMesaGivesACoreProfileOfAtLeast33) {
    const auto context = create_offscreen_context("osmesa");
    EXPECT_EQ(context->backend(), "osmesa");
    EXPECT_GE(current_version(), 33);
    EXPECT_TRUE(current_profile() & GL_CONTEXT_CORE_PROFILE_BIT);
    EXPECT_TRUE(contains(gl_description(), "Core Profile") || current_version() >= 33);
}

TEST(Context, EglSurfacelessGivesACoreProfileOfAtLeast33) {
    // Mesa's surfaceless platform needs no display and no GPU (scripts/setup.sh installs it).
    const auto context = create_offscreen_context("egl");
    EXPECT_EQ(context->backend(), "egl");
    EXPECT_GE(current_version(), 33);
    EXPECT_TRUE(current_profile() & GL_CONTEXT_CORE_PROFILE_BIT);
}

TEST(Context, AutoPicksTheFirstBackendThatWorks) {
    const auto context = create_offscreen_context("auto");
    EXPECT_EQ(context->backend(), "osmesa");
}

TEST(Context, AnUnavailableVersionFailsWithTheBackendsReason) {
    // Mesa's software driver offers at most 4.5; 9.9 fails on every back end.
    const auto osmesa = [] { create_offscreen_context("osmesa", GlVersion{9, 9}); };
    expect_error<std::runtime_error>(osmesa, {"OSMesa", "9.9"});
    // One line that gives the reason of each back end tried.
    const auto any = [] { create_offscreen_context("auto", GlVersion{9, 9}); };
    const std::string message = error_of<std::runtime_error>(any);
    expect_contains(message, {"no offscreen OpenGL context", "OSMesa", "EGL"});
    EXPECT_FALSE(contains(message, "\n")) << message;
}

TEST(Context, ContextsOfBothKindsCanTakeTurns) {
    // One loader serves both: switching reloads the functions of the context made current.
    const auto osmesa = create_offscreen_context("osmesa");
    const auto egl = create_offscreen_context("egl");
    for (GlContext* c : {osmesa.get(), egl.get(), osmesa.get()}) {
        c->make_current();
        GLuint buffer = 0;
        glGenBuffers(1, &buffer);
        EXPECT_NE(buffer, 0u) << c->backend();
        glDeleteBuffers(1, &buffer);
        EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR)) << c->backend();
    }
}

TEST(Context, AdoptedContextMakesItselfCurrentThroughTheCallback) {
    const auto osmesa = create_offscreen_context("osmesa");
    int calls = 0;
    // Stands in for a GLFW window (glfwMakeContextCurrent + glfwGetProcAddress).
    const auto adopted = adopt_context(
        [&] {
            ++calls;
            osmesa->make_current();
        },
        reinterpret_cast<GlProcLoader>(&OSMesaGetProcAddress));
    EXPECT_EQ(calls, 1);
    EXPECT_EQ(adopted->backend(), "window");
    adopted->make_current();
    EXPECT_EQ(calls, 2);
    EXPECT_GE(current_version(), 33);
    EXPECT_THROW(adopt_context({}, reinterpret_cast<GlProcLoader>(&OSMesaGetProcAddress)),
                 std::invalid_argument);
}

TEST(Context, LoadingWithoutALoaderFails) {
    EXPECT_THROW(load_gl(nullptr), std::runtime_error);
}

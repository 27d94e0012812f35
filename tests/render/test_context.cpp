// Offscreen contexts: the back ends named on the command line, and the errors when a context
// cannot be made.
#include <string>

#include <gtest/gtest.h>

#include "render/context.h" // glad first

#include <GL/osmesa.h>

using namespace snert::render;

namespace {
bool contains(const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
}
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
    try {
        create_offscreen_context("vulkan");
        FAIL() << "no exception";
    } catch (const std::invalid_argument& e) {
        EXPECT_TRUE(contains(e.what(), "'vulkan'")) << e.what();
        EXPECT_TRUE(contains(e.what(), "osmesa")) << e.what();
    }
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
    try {
        create_offscreen_context("osmesa", GlVersion{9, 9});
        FAIL() << "no exception";
    } catch (const std::runtime_error& e) {
        EXPECT_TRUE(contains(e.what(), "OSMesa")) << e.what();
        EXPECT_TRUE(contains(e.what(), "9.9")) << e.what();
    }
    try {
        create_offscreen_context("auto", GlVersion{9, 9});
        FAIL() << "no exception";
    } catch (const std::runtime_error& e) {
        // One line that gives the reason of each back end tried.
        EXPECT_TRUE(contains(e.what(), "no offscreen OpenGL context")) << e.what();
        EXPECT_TRUE(contains(e.what(), "OSMesa")) << e.what();
        EXPECT_TRUE(contains(e.what(), "EGL")) << e.what();
        EXPECT_FALSE(contains(e.what(), "\n")) << e.what();
    }
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

// Offscreen contexts. The recipes (attributes, platform, failure modes) were checked against
// Mesa 22.3 on Debian 12: OSMesa's core profile needs OSMesaCreateContextAttribs, and EGL must
// be asked for the surfaceless Mesa platform explicitly, because eglGetDisplay with no
// DISPLAY tries X11 and fails.
//
// OSMesa is opened with dlopen when the first OSMesa context is made, not linked: it pulls in
// LLVM (llvmpipe), whose load alone costs every command about 50 MB of resident memory and a
// tenth of a second, although only `render`, `gui` and the tests draw anything.
#include "context.h"

#include "gl.h" // glad before any other GL header

#include <GL/osmesa.h>

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <dlfcn.h>

#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <vector>

namespace snert::render {

namespace {

std::string version_text(GlVersion v) {
    return std::to_string(v.major) + "." + std::to_string(v.minor) + " core";
}

// The four OSMesa entry points snert calls, resolved once from the library's run-time name.
struct OsMesaLibrary {
    decltype(&OSMesaCreateContextAttribs) create_context_attribs = nullptr;
    decltype(&OSMesaDestroyContext) destroy_context = nullptr;
    decltype(&OSMesaMakeCurrent) make_current = nullptr;
    decltype(&OSMesaGetProcAddress) get_proc_address = nullptr;
};

template <class Function> void resolve(void* library, const char* name, Function& out) {
    out = reinterpret_cast<Function>(dlsym(library, name));
    if (out == nullptr)
        throw std::runtime_error(std::string("cannot use OSMesa: the library lacks ") + name);
}

OsMesaLibrary open_osmesa() {
    void* library = nullptr;
    std::string reasons;
    // The versioned name is the one the run-time package installs; the plain one is the -dev
    // package's link.
    for (const char* name : {"libOSMesa.so.8", "libOSMesa.so"}) {
        library = dlopen(name, RTLD_NOW | RTLD_LOCAL);
        if (library != nullptr) break;
        const char* why = dlerror();
        reasons += (reasons.empty() ? "" : "; ") + std::string(why ? why : name);
    }
    if (library == nullptr) throw std::runtime_error("cannot open OSMesa (" + reasons + ")");
    // Never closed: the GL functions loaded through it stay in use until the process ends.
    OsMesaLibrary functions;
    resolve(library, "OSMesaCreateContextAttribs", functions.create_context_attribs);
    resolve(library, "OSMesaDestroyContext", functions.destroy_context);
    resolve(library, "OSMesaMakeCurrent", functions.make_current);
    resolve(library, "OSMesaGetProcAddress", functions.get_proc_address);
    return functions;
}

const OsMesaLibrary& osmesa() {
    static const OsMesaLibrary library = open_osmesa(); // thread-safe, retried after a throw
    return library;
}

class OsMesaContext final : public GlContext {
  public:
    explicit OsMesaContext(GlVersion version) : library_(osmesa()) {
        const int attributes[] = {OSMESA_FORMAT,
                                  OSMESA_RGBA,
                                  OSMESA_DEPTH_BITS,
                                  24,
                                  OSMESA_STENCIL_BITS,
                                  8,
                                  OSMESA_PROFILE,
                                  OSMESA_CORE_PROFILE,
                                  OSMESA_CONTEXT_MAJOR_VERSION,
                                  version.major,
                                  OSMESA_CONTEXT_MINOR_VERSION,
                                  version.minor,
                                  0};
        context_ = library_.create_context_attribs(attributes, nullptr);
        if (context_ == nullptr)
            throw std::runtime_error("cannot create an OSMesa OpenGL " + version_text(version) +
                                     " context (OSMesaCreateContextAttribs failed)");
        try {
            make_current();
        } catch (...) {
            library_.destroy_context(context_);
            throw;
        }
    }
    ~OsMesaContext() override { library_.destroy_context(context_); }

    void make_current() override {
        // The default framebuffer is never drawn to (everything goes to a RenderTarget), so a
        // tiny colour buffer suffices; OSMesa only needs one to make the context current.
        if (!library_.make_current(context_, buffer_.data(), GL_UNSIGNED_BYTE, kSide, kSide))
            throw std::runtime_error("cannot make the OSMesa context current");
        load_gl(reinterpret_cast<GlProcLoader>(library_.get_proc_address));
    }
    std::string_view backend() const override { return "osmesa"; }

  private:
    static constexpr int kSide = 4;
    const OsMesaLibrary& library_;
    OSMesaContext context_ = nullptr;
    std::vector<std::uint8_t> buffer_ = std::vector<std::uint8_t>(kSide * kSide * 4);
};

std::string egl_error_text() {
    char code[16];
    std::snprintf(code, sizeof code, "0x%04x", static_cast<unsigned>(eglGetError()));
    return std::string("EGL error ") + code;
}

class EglContext final : public GlContext {
  public:
    explicit EglContext(GlVersion version) {
        const std::string what = "cannot create an EGL OpenGL " + version_text(version) +
                                 " context (surfaceless Mesa platform): ";
        auto get_platform_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
            eglGetProcAddress("eglGetPlatformDisplayEXT"));
        if (get_platform_display == nullptr)
            throw std::runtime_error(what + "eglGetPlatformDisplayEXT is missing");
        display_ =
            get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
        if (display_ == EGL_NO_DISPLAY) throw std::runtime_error(what + "no display");
        EGLint major = 0, minor = 0;
        if (!eglInitialize(display_, &major, &minor))
            throw std::runtime_error(what + "eglInitialize failed, " + egl_error_text());
        create(version, what);
    }
    ~EglContext() override {
        eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        eglDestroyContext(display_, context_);
        // The display stays initialised: it is one per process, shared by every EGL context
        // (eglTerminate would pull it from under the others), and the driver stays loaded.
        eglReleaseThread();
    }

    void make_current() override {
        if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_))
            throw std::runtime_error("cannot make the EGL context current, " + egl_error_text());
        load_gl(reinterpret_cast<GlProcLoader>(&eglGetProcAddress));
    }
    std::string_view backend() const override { return "egl"; }

  private:
    void create(GlVersion version, const std::string& what) {
        if (!eglBindAPI(EGL_OPENGL_API))
            throw std::runtime_error(what + "eglBindAPI(OpenGL) failed, " + egl_error_text());
        // The surfaceless platform has no window configs, and EGL_SURFACE_TYPE defaults to
        // EGL_WINDOW_BIT: ask for pbuffer-capable ones (no surface is made; we draw to FBOs).
        const EGLint config_attributes[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE,
                                            EGL_PBUFFER_BIT, EGL_NONE};
        EGLConfig config = nullptr;
        EGLint count = 0;
        if (!eglChooseConfig(display_, config_attributes, &config, 1, &count) || count < 1)
            throw std::runtime_error(what + "no OpenGL config, " + egl_error_text());
        const EGLint context_attributes[] = {EGL_CONTEXT_MAJOR_VERSION,
                                             version.major,
                                             EGL_CONTEXT_MINOR_VERSION,
                                             version.minor,
                                             EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                             EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                             EGL_NONE};
        context_ = eglCreateContext(display_, config, EGL_NO_CONTEXT, context_attributes);
        if (context_ == EGL_NO_CONTEXT)
            throw std::runtime_error(what + "eglCreateContext failed, " + egl_error_text());
        try {
            make_current();
        } catch (...) {
            eglDestroyContext(display_, context_);
            throw;
        }
    }
    EGLDisplay display_ = EGL_NO_DISPLAY;
    EGLContext context_ = EGL_NO_CONTEXT;
};

class AdoptedContext final : public GlContext {
  public:
    AdoptedContext(std::function<void()> activate, GlProcLoader loader)
        : make_current_(std::move(activate)), loader_(loader) {
        if (!make_current_) throw std::invalid_argument("adopt_context: no make_current given");
        make_current();
    }
    void make_current() override {
        make_current_();
        load_gl(loader_);
    }
    std::string_view backend() const override { return "window"; }

  private:
    std::function<void()> make_current_;
    GlProcLoader loader_;
};

std::unique_ptr<GlContext> create_named(std::string_view backend, GlVersion version) {
    if (backend == "osmesa") return std::make_unique<OsMesaContext>(version);
    if (backend == "egl") return std::make_unique<EglContext>(version);
    throw std::invalid_argument("unknown GL backend '" + std::string(backend) +
                                "' (choose osmesa, egl or auto)");
}

} // namespace

std::vector<std::string> offscreen_backends() {
    return {"osmesa", "egl"};
}

std::unique_ptr<GlContext> create_offscreen_context(std::string_view backend, GlVersion version) {
    if (backend != "auto") return create_named(backend, version);
    std::string reasons;
    for (const std::string& name : offscreen_backends()) {
        try {
            return create_named(name, version);
        } catch (const std::runtime_error& e) {
            reasons += (reasons.empty() ? "" : "; ") + std::string(e.what());
        }
    }
    throw std::runtime_error("no offscreen OpenGL context could be created: " + reasons);
}

std::unique_ptr<GlContext> adopt_context(std::function<void()> make_current, GlProcLoader loader) {
    return std::make_unique<AdoptedContext>(std::move(make_current), loader);
}

} // namespace snert::render

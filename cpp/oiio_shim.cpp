// prism ↔ OpenImageIO shim (see oiio_shim.h). Catches every exception at the boundary.
#include "oiio_shim.h"

#include <OpenImageIO/imageio.h>

#include <cstdio>
#include <cstring>
#include <exception>
#include <mutex>
#include <string>

#include <unistd.h>

using OIIO::ImageInput;
using OIIO::ImageOutput;
using OIIO::ImageSpec;
using OIIO::TypeDesc;

namespace {

void set_error(char *err, size_t err_len, const std::string &msg) {
    if (err == nullptr || err_len == 0) return;
    // One line: OIIO messages sometimes carry newlines.
    std::string line = msg.empty() ? std::string("unknown OpenImageIO error") : msg;
    for (char &c : line)
        if (c == '\n' || c == '\r') c = ' ';
    while (!line.empty() && line.back() == ' ') line.pop_back();
    size_t n = line.size() < err_len - 1 ? line.size() : err_len - 1;
    std::memcpy(err, line.data(), n);
    err[n] = '\0';
}

// The pending global error, or `fallback` when OIIO has none.
std::string global_error(const std::string &fallback) {
    std::string e = OIIO::geterror();
    return e.empty() ? fallback : e;
}

bool to_typedesc(int format, TypeDesc &out) {
    switch (format) {
    case PRISM_OIIO_HALF: out = TypeDesc::HALF; return true;
    case PRISM_OIIO_FLOAT: out = TypeDesc::FLOAT; return true;
    case PRISM_OIIO_UINT8: out = TypeDesc::UINT8; return true;
    case PRISM_OIIO_UINT16: out = TypeDesc::UINT16; return true;
    default: return false;
    }
}

int from_typedesc(TypeDesc t) {
    if (t == TypeDesc::HALF) return PRISM_OIIO_HALF;
    if (t == TypeDesc::FLOAT) return PRISM_OIIO_FLOAT;
    if (t == TypeDesc::UINT8) return PRISM_OIIO_UINT8;
    if (t == TypeDesc::UINT16) return PRISM_OIIO_UINT16;
    return PRISM_OIIO_OTHER;
}

// Names matching the Rust backend: Y, YA, RGB, RGBA.
void name_channels(ImageSpec &spec, int channels) {
    spec.channelnames.clear();
    switch (channels) {
    case 1: spec.channelnames = {"Y"}; spec.alpha_channel = -1; break;
    case 2: spec.channelnames = {"Y", "A"}; spec.alpha_channel = 1; break;
    case 3: spec.channelnames = {"R", "G", "B"}; spec.alpha_channel = -1; break;
    default: spec.default_channel_names(); break;
    }
}

bool set_attributes(ImageSpec &spec, const prism_oiio_attr *attrs, int count) {
    for (int i = 0; i < count; ++i) {
        const prism_oiio_attr &a = attrs[i];
        if (a.name == nullptr) return false;
        switch (a.type) {
        case PRISM_OIIO_ATTR_FLOAT:
            if (a.values == nullptr) return false;
            spec.attribute(a.name, a.values[0]);
            break;
        case PRISM_OIIO_ATTR_INT: spec.attribute(a.name, a.int_value); break;
        case PRISM_OIIO_ATTR_STRING:
            if (a.text == nullptr) return false;
            spec.attribute(a.name, a.text);
            break;
        case PRISM_OIIO_ATTR_M44F:
            if (a.values == nullptr) return false;
            spec.attribute(a.name, OIIO::TypeMatrix44, a.values);
            break;
        case PRISM_OIIO_ATTR_FLOAT8:
            if (a.values == nullptr) return false;
            spec.attribute(a.name, TypeDesc(TypeDesc::FLOAT, 8), a.values);
            break;
        default: return false;
        }
    }
    return true;
}

int write_impl(const char *path, int width, int height, int channels, const float *pixels,
               int format, int quality, const int *window, const prism_oiio_attr *attrs,
               int attr_count, char *err, size_t err_len) {
    TypeDesc type;
    if (!to_typedesc(format, type)) {
        set_error(err, err_len, "unknown pixel format code " + std::to_string(format));
        return 1;
    }
    if (path == nullptr || pixels == nullptr || width <= 0 || height <= 0 || channels <= 0) {
        set_error(err, err_len, "invalid arguments to prism_oiio_write_meta");
        return 1;
    }
    auto out = ImageOutput::create(path);
    if (!out) {
        set_error(err, err_len, global_error(std::string("cannot create a writer for ") + path));
        return 1;
    }
    ImageSpec spec(width, height, channels, type);
    name_channels(spec, channels);
    if (window != nullptr && window[2] > 0 && window[3] > 0) {
        /* A crop: its pixels are the data window inside the full image's display window. */
        spec.x = window[0];
        spec.y = window[1];
        spec.full_x = 0;
        spec.full_y = 0;
        spec.full_width = window[2];
        spec.full_height = window[3];
    }
    // The caller's alpha is straight (unassociated): store it as given.
    spec.attribute("oiio:UnassociatedAlpha", 1);
    if (out->format_name() == std::string("openexr")) spec.attribute("compression", "zip");
    if (quality > 0) spec.attribute("CompressionQuality", quality);
    if (attr_count < 0 || (attr_count > 0 && attrs == nullptr) ||
        !set_attributes(spec, attrs, attr_count)) {
        set_error(err, err_len, "invalid header attributes to prism_oiio_write_meta");
        return 1;
    }
    if (!out->open(path, spec)) {
        set_error(err, err_len, out->geterror());
        return 1;
    }
    bool ok = out->write_image(TypeDesc::FLOAT, pixels);
    std::string write_err = ok ? std::string() : out->geterror();
    if (!out->close() && ok) {
        ok = false;
        write_err = out->geterror();
    }
    if (!ok) {
        set_error(err, err_len, write_err);
        return 1;
    }
    return 0;
}

// Holds back what the codec libraries print to stderr while a file is read. OpenImageIO 2.4's PNG
// reader leaves libpng's default error handler in place, which prints "libpng error: ..." before
// OpenImageIO reports the same message itself, and no OpenImageIO attribute turns that off; so
// file descriptor 2 goes to a temporary file for the duration of the call (a process-wide mutex
// serialises the readers). On release the libraries' own "libpng ..." lines are dropped when the
// read failed (its error already carries them); every other captured line goes back to stderr.
class StderrCapture {
  public:
    StderrCapture() : lock_(mutex()) {
        std::fflush(stderr);
        file_ = std::tmpfile();
        saved_ = file_ ? dup(2) : -1;
        if (saved_ >= 0 && dup2(fileno(file_), 2) < 0) {
            close(saved_);
            saved_ = -1;
        }
    }
    StderrCapture(const StderrCapture &) = delete;
    StderrCapture &operator=(const StderrCapture &) = delete;
    void failed() { failed_ = true; }
    ~StderrCapture() {
        std::fflush(stderr);
        if (saved_ >= 0) {
            dup2(saved_, 2);
            close(saved_);
            forward();
        }
        if (file_) std::fclose(file_);
    }

  private:
    static std::mutex &mutex() {
        static std::mutex m;
        return m;
    }
    void forward() {
        std::rewind(file_);
        char buf[4096];
        std::string text;
        size_t n;
        while ((n = std::fread(buf, 1, sizeof buf, file_)) > 0) text.append(buf, n);
        size_t start = 0;
        while (start < text.size()) {
            size_t end = text.find('\n', start);
            if (end == std::string::npos) end = text.size();
            std::string line = text.substr(start, end - start);
            start = end + 1;
            if (line.empty() || (failed_ && line.rfind("libpng", 0) == 0)) continue;
            std::fprintf(stderr, "%s\n", line.c_str());
        }
    }
    std::lock_guard<std::mutex> lock_;
    std::FILE *file_ = nullptr;
    int saved_ = -1;
    bool failed_ = false;
};

std::unique_ptr<ImageInput> open_input(const char *path) {
    ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    return ImageInput::open(path, &config);
}

int read_info_impl(const char *path, int *width, int *height, int *channels, int *format,
                   char *err, size_t err_len) {
    if (path == nullptr || width == nullptr || height == nullptr || channels == nullptr ||
        format == nullptr) {
        set_error(err, err_len, "invalid arguments to prism_oiio_read_info");
        return 1;
    }
    StderrCapture capture;
    auto in = open_input(path);
    if (!in) {
        capture.failed();
        set_error(err, err_len, global_error(std::string("cannot open ") + path));
        return 1;
    }
    const ImageSpec &spec = in->spec();
    *width = spec.width;
    *height = spec.height;
    *channels = spec.nchannels;
    *format = from_typedesc(spec.format);
    in->close();
    return 0;
}

int read_impl(const char *path, int width, int height, int channels, float *pixels,
              size_t pixel_count, char *err, size_t err_len) {
    if (path == nullptr || pixels == nullptr) {
        set_error(err, err_len, "invalid arguments to prism_oiio_read");
        return 1;
    }
    StderrCapture capture;
    auto in = open_input(path);
    if (!in) {
        capture.failed();
        set_error(err, err_len, global_error(std::string("cannot open ") + path));
        return 1;
    }
    const ImageSpec &spec = in->spec();
    if (spec.width != width || spec.height != height || spec.nchannels != channels ||
        static_cast<size_t>(width) * static_cast<size_t>(height) * static_cast<size_t>(channels) !=
            pixel_count) {
        set_error(err, err_len, "image size changed between info and read");
        return 1;
    }
    if (!in->read_image(0, 0, 0, channels, TypeDesc::FLOAT, pixels)) {
        capture.failed();
        set_error(err, err_len, in->geterror());
        return 1;
    }
    in->close();
    return 0;
}

} // namespace

extern "C" int prism_oiio_write_meta(const char *path, int width, int height, int channels,
                                     const float *pixels, int format, int quality,
                                     const int *window, const prism_oiio_attr *attrs,
                                     int attr_count, char *err, size_t err_len) {
    try {
        return write_impl(path, width, height, channels, pixels, format, quality, window, attrs,
                          attr_count, err, err_len);
    } catch (const std::exception &e) {
        set_error(err, err_len, e.what());
    } catch (...) {
        set_error(err, err_len, "unknown C++ exception in prism_oiio_write_meta");
    }
    return 1;
}

extern "C" int prism_oiio_read_info(const char *path, int *width, int *height, int *channels,
                                    int *format, char *err, size_t err_len) {
    try {
        return read_info_impl(path, width, height, channels, format, err, err_len);
    } catch (const std::exception &e) {
        set_error(err, err_len, e.what());
    } catch (...) {
        set_error(err, err_len, "unknown C++ exception in prism_oiio_read_info");
    }
    return 1;
}

extern "C" int prism_oiio_read(const char *path, int width, int height, int channels,
                               float *pixels, size_t pixel_count, char *err, size_t err_len) {
    try {
        return read_impl(path, width, height, channels, pixels, pixel_count, err, err_len);
    } catch (const std::exception &e) {
        set_error(err, err_len, e.what());
    } catch (...) {
        set_error(err, err_len, "unknown C++ exception in prism_oiio_read");
    }
    return 1;
}

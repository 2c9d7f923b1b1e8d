/* image_io.cpp - PNG and EXR encoding and decoding of lucent_image through OpenImageIO.
 * The project's one C++ file: a thin extern "C" layer; no C++ exception crosses it. */
#include "lucent.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <new>
#include <string>
#include <vector>

namespace {

using Bytes = std::vector<unsigned char>;

/* How radiance becomes output pixels: the exposure factor and what lies behind the object. */
struct Look {
    double scale; /* 2^exposure */
    const double *background;
};

/* The object "over" the background. Radiance is already weighted by coverage (edge pixels
 * hold partial radiance), so only the background is attenuated; the result is premultiplied. */
void composite(const float *rgba, const Look &look, double out[4])
{
    double a = rgba[3];
    for (int c = 0; c < 3; c++)
        out[c] = rgba[c] * look.scale + look.background[c] * (1.0 - a);
    out[3] = a + look.background[3] * (1.0 - a);
}

/* The exact piecewise sRGB curves (IEC 61966-2-1), not the 2.2 power approximation. */
double srgb_encode(double v)
{
    return v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
}

double srgb_decode(double v)
{
    return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
}

/* Non-finite values have no 8-bit meaning; 0 keeps a stray NaN from painting a pixel white. */
unsigned char unorm8(double v)
{
    if (!std::isfinite(v))
        return 0;
    return (unsigned char)std::lround(std::clamp(v, 0.0, 1.0) * 255.0);
}

/* PNG stores straight alpha, so colour is divided by the composited alpha before encoding. */
void png_row(const lucent_image *img, int y, const Look &look, unsigned char *row)
{
    for (int x = 0; x < img->width; x++) {
        double px[4];
        composite(img->rgba + ((size_t)y * img->width + x) * 4, look, px);
        for (int c = 0; c < 3; c++)
            row[x * 4 + c] = px[3] > 0.0 ? unorm8(srgb_encode(px[c] / px[3])) : 0;
        row[x * 4 + 3] = unorm8(px[3]);
    }
}

/* One EXR row in the channel order exr_spec() declares; values pass through unclamped. */
void exr_row(const lucent_image *img, int y, const Look &look, float *row)
{
    for (int x = 0; x < img->width; x++) {
        size_t i = (size_t)y * img->width + x;
        double px[4];
        composite(img->rgba + i * 4, look, px);
        row = std::copy(px, px + 4, row);
        if (img->depth)
            *row++ = img->depth[i];
        if (img->normal)
            row = std::copy(img->normal + i * 3, img->normal + i * 3 + 3, row);
        if (img->view)
            *row++ = img->view[i];
        if (img->facing)
            *row++ = img->facing[i];
    }
}

OIIO::ImageSpec png_spec(const lucent_image *img)
{
    OIIO::ImageSpec spec(img->width, img->height, 4, OIIO::TypeDesc::UINT8);
    spec.attribute("oiio:ColorSpace", "sRGB"); /* writes the sRGB, gAMA and cHRM chunks */
    /* Our bytes are already straight; without this OIIO would divide colour by alpha again. */
    spec.attribute("oiio:UnassociatedAlpha", 1);
    /* zlib level 1 without row filters: at 512^2 libpng's default (level 6, adaptive filters) took
     * as long as the render itself (~66 ms) and this ~9 ms, for files about 25% larger (96 -> 121 KB
     * on the demo scene). A render service spends its time rendering, not squeezing bytes. */
    spec.attribute("png:compressionLevel", 1);
    spec.attribute("png:filter", 0x08); /* PNG_FILTER_NONE */
    return spec;
}

/* float32, not half: subsurface radiance spans more range than half holds (research note,
 * failure mode 11). */
OIIO::ImageSpec exr_spec(const lucent_image *img)
{
    std::vector<std::string> names = {"R", "G", "B", "A"};
    if (img->depth)
        names.push_back("Z");
    if (img->normal)
        names.insert(names.end(), {"N.X", "N.Y", "N.Z"});
    if (img->view)
        names.push_back("view");
    if (img->facing)
        names.push_back("facing");
    OIIO::ImageSpec spec(img->width, img->height, (int)names.size(), OIIO::TypeDesc::FLOAT);
    spec.channelnames = names;
    spec.attribute("compression", "zip");
    /* OpenImageIO stamps an EXR with the time it was written (capDate) unless a DateTime is given; one
     * that is not a string counts as given and is never written, so one scene always gives one file (its
     * strong ETag promises that, on every replica and after every restart). */
    spec.attribute("DateTime", 0);
    return spec;
}

/* Feeds the writer one converted row at a time so no second full-size copy of the image exists. */
template <typename T, typename FillRow>
bool write_rows(OIIO::ImageOutput &out, const OIIO::ImageSpec &spec, FillRow fill_row)
{
    std::vector<T> row((size_t)spec.width * spec.nchannels);
    for (int y = 0; y < spec.height; y++) {
        fill_row(y, row.data());
        if (!out.write_scanline(y, 0, spec.format, row.data()))
            return false;
    }
    return true;
}

bool write_pixels(OIIO::ImageOutput &out, const OIIO::ImageSpec &spec, const lucent_image *img,
                  const Look &look)
{
    if (spec.format == OIIO::TypeDesc::UINT8)
        return write_rows<unsigned char>(
            out, spec, [&](int y, unsigned char *row) { png_row(img, y, look, row); });
    return write_rows<float>(out, spec, [&](int y, float *row) { exr_row(img, y, look, row); });
}

/* The one path from pixels to file bytes; lucent_image_write stores what this produces. */
lucent_status encode(const lucent_image *img, lucent_format format, const Look &look,
                     Bytes &bytes, lucent_error *err)
{
    bool png = format == LUCENT_FORMAT_PNG;
    const char *kind = png ? "PNG" : "EXR";
    /* The name only picks OpenImageIO's plugin; the bytes go to the proxy. */
    const char *name = png ? "lucent.png" : "lucent.exr";
    OIIO::Filesystem::IOVecOutput proxy(bytes); /* declared first: it must outlive the writer */
    auto out = OIIO::ImageOutput::create(name, &proxy);
    if (!out)
        return lucent_fail(err, LUCENT_E_IO, "format", "OpenImageIO has no %s writer: %s", kind,
                           OIIO::geterror().c_str());
    OIIO::ImageSpec spec = png ? png_spec(img) : exr_spec(img);
    if (!out->open(name, spec))
        return lucent_fail(err, LUCENT_E_IO, "", "encoding %s: %s", kind, out->geterror().c_str());
    bool ok = write_pixels(*out, spec, img, look);
    /* close() flushes the last compressed blocks and must run even after a failed row. */
    ok = out->close() && ok;
    if (!ok)
        return lucent_fail(err, LUCENT_E_IO, "", "encoding %s: %s", kind, out->geterror().c_str());
    return LUCENT_OK;
}

/* Both directions hold the whole image in memory, so both refuse what the renderer may not make. */
lucent_status check_size(int width, int height, const char *what, lucent_error *err)
{
    if (width < 1 || width > LUCENT_MAX_IMAGE_SIDE || height < 1 || height > LUCENT_MAX_IMAGE_SIDE)
        return lucent_fail(err, LUCENT_E_LIMIT, "", "%s is %dx%d; each side must be 1 to %d", what,
                           width, height, LUCENT_MAX_IMAGE_SIDE);
    return LUCENT_OK;
}

lucent_status check_encode_args(const lucent_image *img, lucent_format format, double exposure,
                                const double background[4], lucent_error *err)
{
    if (!img || !img->rgba)
        return lucent_fail(err, LUCENT_E_INVALID, "", "image has no rgba pixels");
    lucent_status st = check_size(img->width, img->height, "image", err);
    if (st != LUCENT_OK)
        return st;
    if (format != LUCENT_FORMAT_PNG && format != LUCENT_FORMAT_EXR)
        return lucent_fail(err, LUCENT_E_INVALID, "format", "unknown image format %d", (int)format);
    /* Written as a negated <= so that NaN is refused too. */
    if (!(std::fabs(exposure) <= LUCENT_MAX_EXPOSURE))
        return lucent_fail(err, LUCENT_E_LIMIT, "exposure", "exposure %g is outside +-%g stops",
                           exposure, LUCENT_MAX_EXPOSURE);
    if (!background)
        return lucent_fail(err, LUCENT_E_INVALID, "background", "background is NULL");
    return LUCENT_OK;
}

lucent_status encode_checked(const lucent_image *img, lucent_format format, double exposure,
                             const double background[4], Bytes &bytes, lucent_error *err)
{
    lucent_status st = check_encode_args(img, format, exposure, background, err);
    if (st != LUCENT_OK)
        return st;
    return encode(img, format, Look{std::exp2(exposure), background}, bytes, err);
}

/* A failed write removes the file so no truncated image is left behind for a client to fetch. */
lucent_status store_file(const char *path, const Bytes &bytes, lucent_error *err)
{
    FILE *f = std::fopen(path, "wb");
    if (!f)
        return lucent_fail(err, LUCENT_E_IO, "", "cannot create %s: %s", path,
                           std::strerror(errno));
    bool ok = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
    int saved = errno;
    if (std::fclose(f) != 0 && ok) {
        ok = false;
        saved = errno;
    }
    if (ok)
        return LUCENT_OK;
    std::remove(path);
    return lucent_fail(err, LUCENT_E_IO, "", "cannot write %s: %s", path, std::strerror(saved));
}

/* Reads one channel into every `stride`-th float of dst, converting to float on the way. */
bool read_channel(OIIO::ImageInput &in, int channel, float *dst, int stride)
{
    const OIIO::ImageSpec &spec = in.spec();
    OIIO::stride_t xstride = stride * (OIIO::stride_t)sizeof(float);
    return in.read_image(0, 0, channel, channel + 1, OIIO::TypeDesc::FLOAT, dst, xstride,
                         xstride * spec.width);
}

/* An AOV of names.size() channels, interleaved into dst; dst is freed and cleared when the file
 * lacks any of them, because the API promises NULL for absent AOVs. */
bool read_aov(OIIO::ImageInput &in, const std::vector<const char *> &names, float *&dst)
{
    std::vector<int> index;
    for (const char *name : names)
        index.push_back(in.spec().channelindex(name));
    if (std::find(index.begin(), index.end(), -1) != index.end()) {
        std::free(dst);
        dst = nullptr;
        return true;
    }
    for (size_t i = 0; i < index.size(); i++)
        if (!read_channel(in, index[i], dst + i, (int)names.size()))
            return false;
    return true;
}

/* The caller has checked that R, G and B exist; a file without A is opaque. */
bool read_rgba(OIIO::ImageInput &in, lucent_image &img)
{
    const char *names[3] = {"R", "G", "B"};
    for (int c = 0; c < 3; c++)
        if (!read_channel(in, in.spec().channelindex(names[c]), img.rgba + c, 4))
            return false;
    int alpha = in.spec().channelindex("A");
    if (alpha >= 0)
        return read_channel(in, alpha, img.rgba + 3, 4);
    for (size_t i = 0; i < (size_t)img.width * img.height; i++)
        img.rgba[i * 4 + 3] = 1.0f;
    return true;
}

/* PNG holds sRGB colour with straight alpha; the renderer's convention is linear premultiplied. */
void png_to_linear(lucent_image &img)
{
    for (size_t i = 0; i < (size_t)img.width * img.height; i++) {
        float *px = img.rgba + i * 4;
        for (int c = 0; c < 3; c++)
            px[c] = (float)(srgb_decode(px[c]) * px[3]);
    }
}

/* Pixels of a PNG or EXR already opened; img is allocated here and freed again on failure. */
lucent_status decode(OIIO::ImageInput &in, const char *path, lucent_image &img, lucent_error *err)
{
    const OIIO::ImageSpec &spec = in.spec();
    std::string format = in.format_name();
    if (format != "png" && format != "openexr")
        return lucent_fail(err, LUCENT_E_IO, "", "%s is %s, not PNG or EXR", path, format.c_str());
    for (const char *name : {"R", "G", "B"})
        if (spec.channelindex(name) < 0)
            return lucent_fail(err, LUCENT_E_IO, "", "%s has no %s channel", path, name);
    lucent_status st = check_size(spec.width, spec.height, path, err);
    if (st == LUCENT_OK)
        st = lucent_image_alloc(&img, spec.width, spec.height, format == "openexr", err);
    if (st != LUCENT_OK)
        return st;
    bool ok = read_rgba(in, img);
    if (format == "png") {
        png_to_linear(img);
    } else {
        ok = ok && read_aov(in, {"Z"}, img.depth) &&
             read_aov(in, {"N.X", "N.Y", "N.Z"}, img.normal) && read_aov(in, {"view"}, img.view) &&
             read_aov(in, {"facing"}, img.facing);
    }
    if (ok)
        return LUCENT_OK;
    lucent_image_free(&img);
    return lucent_fail(err, LUCENT_E_IO, "", "reading %s: %s", path, in.geterror().c_str());
}

lucent_status load(const char *path, lucent_image &img, lucent_error *err)
{
    OIIO::ImageSpec config;
    /* Without this OIIO premultiplies PNG colour itself, in sRGB space and rounded to 8 bits. */
    config.attribute("oiio:UnassociatedAlpha", 1);
    auto in = OIIO::ImageInput::open(path, &config);
    if (!in)
        return lucent_fail(err, LUCENT_E_IO, "", "cannot read %s: %s", path,
                           OIIO::geterror().c_str());
    return decode(*in, path, img, err);
}

/* Nothing may throw into C: allocation failure becomes NOMEM, anything else is our bug. */
lucent_status exception_status(lucent_error *err)
{
    try {
        throw;
    } catch (const std::bad_alloc &) {
        return lucent_fail(err, LUCENT_E_NOMEM, "", "out of memory while encoding or decoding");
    } catch (const std::exception &e) {
        return lucent_fail(err, LUCENT_E_INTERNAL, "", "image I/O: %s", e.what());
    } catch (...) {
        return lucent_fail(err, LUCENT_E_INTERNAL, "", "image I/O: unknown exception");
    }
}

} // namespace

extern "C" lucent_status lucent_image_encode(const lucent_image *img, lucent_format format,
                                             double exposure, const double background[4],
                                             unsigned char **bytes, size_t *len, lucent_error *err)
{
    if (!bytes || !len)
        return lucent_fail(err, LUCENT_E_INVALID, "", "lucent_image_encode: bytes or len is NULL");
    *bytes = nullptr;
    *len = 0;
    try {
        Bytes encoded;
        lucent_status st = encode_checked(img, format, exposure, background, encoded, err);
        if (st != LUCENT_OK)
            return st;
        /* The caller frees with free(), so the vector's storage cannot be handed over. */
        unsigned char *copy = (unsigned char *)std::malloc(encoded.size());
        if (!copy)
            return lucent_fail(err, LUCENT_E_NOMEM, "", "out of memory for %zu encoded bytes",
                               encoded.size());
        std::memcpy(copy, encoded.data(), encoded.size());
        *bytes = copy;
        *len = encoded.size();
        return LUCENT_OK;
    } catch (...) {
        return exception_status(err);
    }
}

extern "C" lucent_status lucent_image_write(const char *path, const lucent_image *img,
                                            lucent_format format, double exposure,
                                            const double background[4], lucent_error *err)
{
    if (!path)
        return lucent_fail(err, LUCENT_E_INVALID, "", "lucent_image_write: path is NULL");
    try {
        Bytes encoded;
        lucent_status st = encode_checked(img, format, exposure, background, encoded, err);
        if (st != LUCENT_OK)
            return st;
        return store_file(path, encoded, err);
    } catch (...) {
        return exception_status(err);
    }
}

extern "C" lucent_status lucent_image_load(const char *path, lucent_image *out, lucent_error *err)
{
    if (!path || !out)
        return lucent_fail(err, LUCENT_E_INVALID, "", "lucent_image_load: path or out is NULL");
    *out = lucent_image{};
    try {
        return load(path, *out, err);
    } catch (...) {
        lucent_image_free(out);
        return exception_status(err);
    }
}

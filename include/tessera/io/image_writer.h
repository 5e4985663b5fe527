// Writing surfaces to image files through OpenImageIO, atomically and reproducibly: each image is
// encoded in memory and written by writeFileAtomically (io/atomic_file.h), so a failure (a full
// disk included) throws and leaves the previous file as it was, and the same surface always gives
// the same bytes (no timestamps; SOURCE_DATE_EPOCH, when set, gives a fixed DateTime instead).
// The back buffer goes to PNG (8-bit, bytes as stored) or EXR (half or float); any surface can
// be written in its own format without loss (see writeSurface).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

#include <tessera/buffers/surface.h>

namespace tessera {

enum class ExrPixelType { Half, Float };

// Writes one sample (`sample`, 0..samples-1) of `surface`, picking the file type from the
// extension:
//  - .png / .tif with an 8-bit UNORM format: the stored bytes (sRGB bytes stay sRGB-encoded);
//  - .exr: the values a shader would load (float; UNORM/SNORM decoded), in the format's channels
//    only (R, RG, RGB or RGBA, channel names "R","G","B","A"; depth as "Z"), as half or float;
//    float formats with `Float` are lossless, as are UNORM8/10 and SNORM16 (each code maps to a
//    distinct binary32 value);
//  - .tif with a UINT format: uint32 channels (lossless).
// Throws std::runtime_error naming the file when the writer fails or the pairing of format and
// extension would lose data (e.g. a float surface to .png). Returns fnv1a64 of the file's bytes.
std::uint64_t writeSurface(const Surface& surface, const std::filesystem::path& path,
                  ExrPixelType exrType = ExrPixelType::Float, std::uint32_t sample = 0);
// The stencil plane of a depth-stencil surface as an 8-bit single-channel image ("S"); returns
// fnv1a64 of the file's bytes.
std::uint64_t writeStencil(const Surface& surface, const std::filesystem::path& path, std::uint32_t sample = 0);
// A copy of a single-sample colour surface with alpha set to 1 (RGBA8: byte 255), as a swap
// chain presents it (DXGI ignores back-buffer alpha). `tessera render --out` writes this, so
// image viewers do not show a technique's leftover alpha as transparency; --dump keeps the
// stored alpha. Surfaces without an alpha channel are returned unchanged.
Surface withOpaqueAlpha(const Surface& surface);

// The file extension that `writeSurface` stores `format` in without loss: ".png" for RGBA8
// (UNORM and UNORM_SRGB), ".tif" for UINT, ".exr" otherwise.
std::string losslessExtension(Format format);

} // namespace tessera

// Writing surfaces to image files through OpenImageIO, atomically: the image is written to a
// temporary file beside the target and renamed into place, so a failure leaves no partial file.
#pragma once

#include <string>

#include <tessera/buffers/surface.h>

namespace tessera::cli {

// Writes sample 0 of `surface`: 8-bit colour formats as stored bytes (PNG), float and
// depth formats as 32-bit float (EXR), UINT formats as uint32 channels. Stencil of a
// depth-stencil format goes to a separate image via `writeStencil`. Throws
// std::runtime_error naming the file on failure.
void writeSurface(const Surface& surface, const std::string& path);
void writeStencil(const Surface& surface, const std::string& path);

} // namespace tessera::cli

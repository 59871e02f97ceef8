// JPEG files read with libjpeg itself, not through OpenImageIO's module (image_backend.h), whose
// ~260 libraries took 0.4 s to load for the default scene's two JPEG maps alone. It reads what
// OpenImageIO's JPEG reader (2.4, on the same libjpeg) gave pelt, to the value
// (tests/tools/io/jpeg_reader_test.cpp compares the two on every colour space, subsampling and
// coding libjpeg writes): libjpeg's defaults (its accurate integer DCT, its smooth chroma
// upsampling); grey as one channel "Y", YCbCr and RGB files as R, G, B; CMYK and YCCK files as
// R, G, B, each colour channel times K / 255 rounded, the stored values taken as Adobe's inverted
// CMYK; a file of two components as R, G (which image_io refuses, as before). No alpha, no EXIF
// orientation applied and no ICC profile (OpenImageIO reported both and pelt used neither);
// nothing is declared linear.
//
// A file is refused at libjpeg's first warning or error while its header and rows are decoded,
// its message the reason: a file cut short or corrupt (which libjpeg would finish with grey),
// one whose header libjpeg doubts, a 12-bit file (this libjpeg decodes 8-bit samples only), one
// of more than four components (its scans find none past the fourth). OpenImageIO's open failed
// on the last two; it read the others but left libjpeg's complaint as an error, and pelt refused
// them. Like it, the reader stops at the last row (libjpeg has read up to the marker after the
// last scan by then): what follows is never looked at. A file of more than kMaxJpegScans scans
// is refused too, at the first scan past the limit.
#pragma once

#include <memory>
#include <string>

#include "tools/io/image_backend.h"

namespace pelt::io {

// Each scan walks every block of the components it codes, however few bytes it takes: a
// progressive scan's end-of-band run skips 32767 blocks in a few bits, an arithmetic-coded
// scan's plain blocks cost less than a bit each. So a small file of many scans decodes for long
// (libjpeg-turbo has djpeg -maxscans and TurboJPEG TJPARAM_SCANLIMIT for it): a 4096 x 4096 grey
// progressive file of 704 valid scans, 0.4 MB, kept a render 3.3 s. Encoders write few: libjpeg's
// jpeg_simple_progression 10 for YCbCr and 6 for grey, mozjpeg's searched progressions a few
// tens, a script of one scan a coefficient and component 192 for YCbCr; a sequential file has
// one scan a component. Yet libjpeg lets a progressive file refine each coefficient bit by bit
// (its own compressor writes up to 704 valid scans a component), and never checks that a
// sequential file sends a component once: a 65 kB arithmetic-coded 4096 x 4096 file, its luma
// scan repeated to 5,000 scans, kept a render 19.6 s, and more copies take longer without end.
// 500 leaves every file an encoder writes alone and bounds the work to 500 walks over the blocks
// (those files are refused in 1.5 and 2.1 s), and the texture-side budget bounds the blocks.
inline constexpr int kMaxJpegScans = 500;

// Opens `file` and reads its header; nullptr with `error` set (libjpeg's reason or the system's)
// when it cannot. The reader's read() takes the file's own channel count and type (8-bit), and
// decodes the file then.
std::unique_ptr<ImageReader> open_jpeg(const std::string& file, std::string& error);

}  // namespace pelt::io

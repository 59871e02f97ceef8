// EXR files written with OpenEXR's own library, not through OpenImageIO's module (image_backend.h):
// loading that module's ~260 libraries took 0.4 s in every process, and an EXR (float colour,
// depth, id, overdraw) is what pixel-accuracy work writes. The file holds what OpenImageIO 2.4's
// EXR writer put there for pelt: the same 32-bit float channels and pixels, ZIP compression in
// blocks of 16 rows at OpenEXR's default level (the same compressed bytes), rows in increasing y,
// the data window equal to the display window at 0, 0, pixel aspect ratio 1, screen window centre
// 0, 0 and width 1; without the empty `capDate` OpenImageIO made of pelt's blank DateTime (a date
// that says nothing, which no reader needs).
#pragma once

#include <string>

namespace pelt::io {

// Writes `width` x `height` pixels of `channels` interleaved floats, rows top to bottom, to
// `file` (created or truncated): 1 channel as "Y", 2 as "Y", "A", 3 as "R", "G", "B", 4 as
// "R", "G", "B", "A", each value's bits as given (NaN, infinities and denormals included).
// Returns "" on success, else the reason (OpenEXR's or the system's), and the caller removes the
// file. A pipe gets a whole file too: see exr_writer.cpp.
std::string write_exr_f32(const std::string& file, int width, int height, int channels, const float* pixels);

// Starts OpenEXR's pool of one thread per core, once a process (later calls return at once), unless
// set_exr_threads set its size; the writer and the reader (exr_reader.h) code their blocks on it.
// May throw OpenEXR's exception when a thread cannot be made.
void start_exr_threads();

// Sizes OpenEXR's pool to `threads` now (0: none, the calling thread codes every block), for a
// command whose --threads must bound the cores it takes: a farm's job of --threads 1 compressed
// its EXR frames on one thread per core. Before a load of OpenImageIO's module on another thread
// (image_backend.h), since no thread can start during it (raster/parallel.h). The count stands:
// start_exr_threads then changes nothing. Throws as start_exr_threads does.
void set_exr_threads(int threads);

}  // namespace pelt::io

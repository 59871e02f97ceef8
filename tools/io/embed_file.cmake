# Writes a C++ source that defines `std::string_view pelt::io::embedded::FUNCTION()`
# returning the bytes of INPUT. Run as: cmake -DINPUT=... -DOUTPUT=... -DFUNCTION=... -P
# embed_file.cmake. Bytes are written as hex so any file (text or binary, any size) works.
file(READ "${INPUT}" hex HEX)
string(LENGTH "${hex}" hex_length)
math(EXPR size "${hex_length} / 2")
string(REGEX REPLACE "([0-9a-f][0-9a-f])" "0x\\1," bytes "${hex}")
string(REGEX REPLACE "((0x..,){16})" "\\1\n    " bytes "${bytes}")
file(WRITE "${OUTPUT}.tmp"
"// Generated from ${INPUT} by tools/io/embed_file.cmake; do not edit.
#include \"tools/io/embedded_data.h\"

namespace pelt::io::embedded {
namespace {
// One extra zero byte so the array is never empty.
const unsigned char kBytes[] = {
    ${bytes}0x00};
}  // namespace

std::string_view ${FUNCTION}() {
  return std::string_view(reinterpret_cast<const char*>(kBytes), ${size});
}

}  // namespace pelt::io::embedded
")
# Replace only when the content changed, so an unchanged asset does not rebuild.
file(COPY_FILE "${OUTPUT}.tmp" "${OUTPUT}" ONLY_IF_DIFFERENT)
file(REMOVE "${OUTPUT}.tmp")

// Checks of an .off file that OpenMesh's OFF reader does not make before it trusts it.
#pragma once

#include <string>
#include <string_view>

namespace ddsimp::io {

// OpenMesh 9.0 reads ASCII OFF with `>>`: a word that is not a number fails the stream and every
// read after it silently keeps its old value, and a face's corner count is read as an unsigned
// int, so a line that is not a face ("-52.4887 ...", 4294967244 corners) makes it push billions
// of vertex handles (gigabytes). This walks the file exactly as that reader does: the header line
// ([ST][C][N]OFF), the three counts, for each vertex x y z (and nx ny nz for NOFF) then the rest
// of its line, for each face its corner count and that many vertex indices then, for COFF, the
// rest of its line (a colour). Returns "" if every word it reads is a number of the kind it
// reads (and, without C, nothing is left on a face's line to be taken for the next face), else
// what is wrong, with the line ("line 10: face 3: '-52.4887' is not a corner count"). Binary OFF
// ("OFF BINARY") is walked the same way by its byte counts: a count the file cannot hold made
// OpenMesh reserve gigabytes. Headers OpenMesh does not read are left to OpenMesh ("").
std::string check_off_file(std::string_view text);

} // namespace ddsimp::io

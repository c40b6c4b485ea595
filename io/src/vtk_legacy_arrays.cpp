#include "vtk_legacy_arrays.h"

#include "text_scanner.h"
#include "vtk_legacy_words.h"

#include <array>
#include <cstdio>
#include <istream>

#include <vtkAbstractArray.h>
#include <vtkDataReader.h>

namespace ddsimp::io::legacy_vtk {

std::string string_values_problem(vtkDataReader& reader, const std::string& type, int64_t values,
                                  std::streamoff file_size) {
    const std::string kind = lower(type);
    const bool strings = kind.rfind("string", 0) == 0 || kind.rfind("utf8_string", 0) == 0;
    const bool variants = kind.rfind("variant", 0) == 0;
    if (!strings && !variants) return "";
    // Each value takes a byte of the file at least; VTK makes an empty one for each it misses.
    if (values > file_size) return std::to_string(values) + " strings, more than the file holds";
    if (strings && reader.GetFileType() != VTK_BINARY) return ""; // lines, checked by the scan
    std::istream& in = *reader.GetIStream();
    const std::ios::iostate state = in.rdstate();
    in.clear();
    const std::streamoff start = in.tellg();
    in.clear(state);
    std::string problem;
    if (variants) {
        for (int64_t i = 0; i < values && problem.empty(); ++i) {
            int value_type = 0;
            std::string word;
            if (!(in >> value_type >> word)) break; // VTK reads empty words from here on
            if (overruns_decode(word))
                problem = "variant " + std::to_string(i) + " " + io::quoted(word) +
                          ": VTK 9.1 reads past a string of one or two characters with a '%'";
        }
    } else {
        char rest[256];
        in.getline(rest, 256); // as VTK reads it
        for (int64_t i = 0; i < values && problem.empty(); ++i) {
            const int first = in.peek();
            uint64_t length = 0;
            const int bytes = first == EOF ? 0 : std::array{8, 4, 2, 1}[first >> 6];
            if (bytes == 1) length = uint64_t(in.get()) & 0x3f;
            for (int b = 0; b < bytes && bytes > 1; ++b) length = length << 8 | uint8_t(in.get());
            if (bytes == 2) length &= 0x3fff;
            if (bytes == 4) length &= 0x3fffffff;
            if (first == EOF || !in) {
                problem = "the file ends in string " + std::to_string(i);
            } else if (length > uint64_t(file_size - in.tellg())) {
                problem = "string " + std::to_string(i) + " is " + std::to_string(length) +
                          " bytes long, more than the file holds";
            } else {
                in.seekg(std::streamoff(length), std::ios::cur);
            }
        }
    }
    in.clear();
    in.seekg(start);
    in.clear(state);
    return problem;
}

std::string field_data_problem(vtkDataReader& reader, VtkMessageCapture& messages, int64_t limit,
                               std::streamoff file_size) {
    char name[1024];
    int arrays = 0;
    if (!reader.ReadString(name) || !reader.Read(&arrays)) return "no name and number of arrays";
    if (arrays < 0 || arrays > limit)
        return std::to_string(arrays) + " arrays, more than the file holds";
    for (int i = 0; i < arrays; ++i) {
        const std::string array = "array " + std::to_string(i);
        char type[1024];
        vtkIdType components = 0, tuples = 0;
        if (!reader.ReadString(name)) return "the file ends before " + array;
        if (std::string(name) == "NULL_ARRAY") continue;
        if (overruns_decode(name))
            return array + " is named " + io::quoted(name) +
                   ": VTK 9.1 reads past a name of one or two characters with a '%'";
        if (!reader.Read(&components) || !reader.Read(&tuples) || !reader.ReadString(type))
            return array + " has no component count, tuple count and type";
        if (components < 0 || tuples < 0 || (components > 0 && tuples > limit / components))
            return array + " declares " + std::to_string(components) + " components of " +
                   std::to_string(tuples) + " tuples, more than the file holds";
        if (std::string problem =
                string_values_problem(reader, type, tuples * components, file_size);
            !problem.empty())
            return array + ": " + problem;
        messages.clear();
        vtkAbstractArray* data = reader.ReadArray(type, tuples, components);
        if (data != nullptr) data->Delete();
        if (data == nullptr || messages.has_error())
            return array + " " + io::quoted(name) + " (" + std::to_string(components) + " x " +
                   std::to_string(tuples) + " " + type +
                   "): " + (messages.has_error() ? messages.first_error() : "VTK cannot read it");
    }
    return "";
}

} // namespace ddsimp::io::legacy_vtk

// The walk's point and cell data: each attribute's header, then its array.
#include "vtk_legacy_walk.h"

#include "text_scanner.h"
#include "vtk_legacy_arrays.h"
#include "vtk_legacy_words.h"

#include <cstdlib>
#include <istream>
#include <vector>

namespace ddsimp::io::legacy_vtk {

std::string DataSetWalk::attributes(bool point_data, vtkIdType count) {
    const std::string of = point_data ? "POINT_DATA" : "CELL_DATA";
    for (char raw[256]; reader_->ReadString(raw);) {
        const std::string word = raw, keyword = lower(raw);
        const std::streamoff word_at = here();
        std::string problem;
        if (starts_with(keyword, "scalars")) {
            problem = scalars(word, count);
        } else if (starts_with(keyword, "vectors") || starts_with(keyword, "normals")) {
            problem = named_array(word, count, 3, true);
        } else if (starts_with(keyword, "tensors6")) {
            problem = named_array(word, count, 6, true);
        } else if (starts_with(keyword, "tensors")) {
            problem = named_array(word, count, 9, true);
        } else if (starts_with(keyword, "texture_coordinates")) {
            problem = texture_coordinates(word, count);
        } else if (starts_with(keyword, "global_ids")) {
            problem = named_array(word, count, 1, true);
        } else if (starts_with(keyword, "pedigree_ids") ||
                   (point_data && starts_with(keyword, "edge_flags"))) {
            problem = named_array(word, count, 1, false);
        } else if (starts_with(keyword, "color_scalars")) {
            problem = color_scalars(word, count);
        } else if (starts_with(keyword, "lookup_table")) {
            problem = lookup_table(word);
        } else if (starts_with(keyword, "field")) {
            problem = field_data_problem(*reader_, messages_, limit_, file_size_);
            if (!problem.empty()) problem = word + " of " + of + " cannot be read: " + problem;
        } else if (starts_with(keyword, point_data ? "cell_data" : "point_data")) {
            // VTK reads the other kind in a call nested in this one: each switch is a
            // deeper stack.
            if (++switches_ > kMostSwitches)
                return at(word_at) + "more than " + std::to_string(kMostSwitches) +
                       " switches between POINT_DATA and CELL_DATA";
            vtkIdType other = 0;
            if (!reader_->Read(&other)) return at(word_at) + word + " has no count";
            if (too_many(other, 1))
                return at(word_at) + word + " " + std::to_string(other) +
                       ": more values than the file holds";
            return attributes(!point_data, other);
        } else {
            return at(word_at) + io::quoted(word) + " is not an attribute of " + of;
        }
        if (!problem.empty()) return at(word_at) + problem;
    }
    return "";
}

std::string DataSetWalk::named_array(const std::string& word, vtkIdType count, vtkIdType components,
                                     bool numeric) {
    char name[256];
    if (!reader_->ReadString(name)) return word + " has no name and type";
    if (overruns_decode(name)) return name_overrun(word, name);
    return array_problem(word + " " + name, count, components, numeric);
}

std::string DataSetWalk::array_problem(const std::string& what, vtkIdType tuples,
                                       vtkIdType components, bool numeric) {
    std::string problem;
    read_array(what, tuples, components, numeric, problem);
    return problem;
}

std::string DataSetWalk::name_overrun(const std::string& word, const char* name) {
    return word + " " + io::quoted(name) +
           ": VTK 9.1 reads past a name of one or two characters with a '%'";
}

std::string DataSetWalk::scalars(const std::string& word, vtkIdType count) {
    char name[256], type[256], key[256], table[256];
    if (!reader_->ReadString(name) || !reader_->ReadString(type) || !reader_->ReadString(key))
        return word + " has no name and type";
    if (overruns_decode(name)) return name_overrun(word, name);
    int components = 1;
    if (lower(key) != "lookup_table") {
        components = std::atoi(key);
        if (components < 1 || !reader_->ReadString(key))
            return word + " " + name + ": " + io::quoted(key) + " is not a component count";
    }
    if (lower(key) != "lookup_table" || !reader_->ReadString(table))
        return word + " " + name + ": no LOOKUP_TABLE name after its type";
    // The type came before the table name.
    std::string problem;
    read_array(word + " " + name, type, count, components, true, problem);
    return problem;
}

std::string DataSetWalk::texture_coordinates(const std::string& word, vtkIdType count) {
    char name[256];
    int dimension = 0;
    if (!reader_->ReadString(name) || !reader_->Read(&dimension))
        return word + " has no name and dimension";
    if (overruns_decode(name)) return name_overrun(word, name);
    if (dimension < 1 || dimension > 3)
        return word + " " + name + ": dimension " + std::to_string(dimension) +
               " (VTK reads 1 to 3)";
    return array_problem(word + " " + name, count, dimension, true);
}

std::string DataSetWalk::color_scalars(const std::string& word, vtkIdType count) {
    char name[256];
    int components = 0;
    if (!reader_->ReadString(name) || !reader_->Read(&components))
        return word + " has no name and component count";
    if (overruns_decode(name)) return name_overrun(word, name);
    std::string problem;
    read_array(word + " " + name, reader_->GetFileType() == VTK_BINARY ? "unsigned_char" : "float",
               count, components, false, problem);
    return problem;
}

std::string DataSetWalk::lookup_table(const std::string& word) {
    char name[256];
    int size = 0;
    if (!reader_->ReadString(name) || !reader_->Read(&size)) return word + " has no name and size";
    const std::string what = word + " " + name + " " + std::to_string(size);
    if (too_many(size, 4)) return what + ": more colours than the file holds";
    std::istream& in = *reader_->GetIStream();
    if (reader_->GetFileType() == VTK_BINARY) {
        char rest[256];
        in.getline(rest, 256); // as VTK reads it
        std::vector<char> bytes(4 * size_t(size));
        in.read(bytes.data(), std::streamsize(bytes.size()));
        if (in.eof()) return what + ": the file ends in its colours";
        return "";
    }
    for (int i = 0; i < 4 * size; ++i) {
        float value = 0;
        if (!reader_->Read(&value))
            return what + ": colour " + std::to_string(i / 4) +
                   " is not 4 numbers, or the file ends in it";
    }
    return "";
}

} // namespace ddsimp::io::legacy_vtk

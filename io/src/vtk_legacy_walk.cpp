// The walk's sections: the points, the cell arrays and cell types, up to the point or cell data.
#include "vtk_legacy_walk.h"

#include "text_scanner.h"
#include "vtk_legacy_arrays.h"
#include "vtk_legacy_cells.h"
#include "vtk_legacy_words.h"

#include <algorithm>
#include <set>
#include <sstream>
#include <vector>

#include <vtkCellArray.h>
#include <vtkDataArray.h>

namespace ddsimp::io::legacy_vtk {

std::string DataSetWalk::problem() {
    if (!reader_->OpenVTKFile(path_.c_str()) || !reader_->ReadHeader(path_.c_str()))
        return ""; // VTK reports a bad header itself
    // vtkDataSetReader reads nothing but "DATASET type" here (else VTK's message has an
    // address in it).
    char word[256];
    if (!reader_->ReadString(word)) return "the file ends after its header";
    if (!starts_with(lower(word), "dataset"))
        return at(here()) + io::quoted(word) + " where DATASET should be";
    if (!reader_->ReadString(word)) return "the file ends after DATASET";
    const std::string type = lower(word);
    // As vtkDataSetReader picks its reader; the others read volumes, not surfaces.
    if (starts_with(type, "structured_points")) return not_a_surface("vtkStructuredPoints");
    if (starts_with(type, "structured_grid")) return not_a_surface("vtkStructuredGrid");
    if (starts_with(type, "rectilinear_grid")) return not_a_surface("vtkRectilinearGrid");
    grid_ = starts_with(type, "unstructured_grid");
    if (!grid_ && !starts_with(type, "polydata"))
        return at(here()) + io::quoted(word) +
               " is not a data set type (POLYDATA, UNSTRUCTURED_GRID, STRUCTURED_POINTS, "
               "STRUCTURED_GRID, RECTILINEAR_GRID)";
    return sections();
}

std::string DataSetWalk::not_a_surface(const std::string& type) {
    return "it holds a " + type +
           ", not a triangle surface (for a volume, use `ddsimp isosurface`)";
}

std::streamoff DataSetWalk::here() const {
    std::istream& in = *reader_->GetIStream();
    const std::ios::iostate state = in.rdstate();
    in.clear();
    const std::streamoff at = in.tellg();
    in.clear(state);
    return std::max<std::streamoff>(at - 1, 0);
}

std::string DataSetWalk::sections() {
    std::string previous;           // the section before
    std::streamoff previous_at = 0; // and where
    std::streamoff field_at = -1;   // a FIELD section just read
    for (char raw[256]; reader_->ReadString(raw);) {
        const std::string word = raw, keyword = lower(raw);
        const std::streamoff word_at = here();
        // VTK takes a misread "cells0" for CELLS, then leaks the cells on its error return:
        // a FIELD section is followed by a whole keyword.
        static const std::set<std::string> keywords{
            "points",   "cells",           "cell_types", "vertices",  "lines",
            "polygons", "triangle_strips", "point_data", "cell_data", "field"};
        if (field_at >= 0 && !keywords.count(keyword))
            return field_problem(field_at,
                                 "it is followed by " + io::quoted(word) + ", not a section");
        field_at = -1;
        std::string problem;
        if (starts_with(keyword, "field")) {
            problem = field_data_problem(*reader_, messages_, limit_, file_size_);
            if (!problem.empty()) return field_problem(word_at, problem);
            field_at = word_at;
        } else if (starts_with(keyword, "points")) {
            problem = points(word);
        } else if (!grid_ &&
                   (starts_with(keyword, "vertices") || starts_with(keyword, "lines") ||
                    starts_with(keyword, "polygons") || starts_with(keyword, "triangle_strips"))) {
            vtkIdType cells = 0;
            problem = cell_array(word, cells);
            poly_cells_[vtk_section(keyword)] = cells; // a second one replaces the first
        } else if (grid_ && starts_with(keyword, "cells")) {
            if (grid_cells_) return at(word_at) + "a second " + word + " section";
            vtkIdType cells = 0;
            problem = cell_array(word, cells);
            grid_cells_ = cells;
            if (major_version() < 5) last_count_ = cells;
            if (problem.empty()) problem = types_for_cells();
        } else if (grid_ && starts_with(keyword, "cell_types")) {
            problem = cell_types(word);
            if (problem.empty()) problem = types_for_cells();
        } else if (starts_with(keyword, "cell_data") || starts_with(keyword, "point_data")) {
            // VTK reads on with the attributes, to the end of the file.
            const bool point_data = starts_with(keyword, "point_data");
            vtkIdType count = 0;
            problem = point_data ? data_count(word, points_, "points", count)
                                 : data_count(word, grid_ ? last_count_ : poly_cell_count(),
                                              "cells", count);
            return problem.empty() ? attributes(point_data, count) : problem;
        } else {
            return at(word_at) + io::quoted(word) + " is not a section keyword" +
                   (previous.empty() ? ""
                                     : "; the section before it is " + previous + " (line " +
                                           std::to_string(line_of(path_, previous_at)) + ")");
        }
        if (!problem.empty()) return at(word_at) + problem;
        previous = word;
        previous_at = word_at;
    }
    return "";
}

std::string DataSetWalk::at(std::streamoff offset) const {
    return "line " + std::to_string(line_of(path_, offset)) + ": ";
}

std::string DataSetWalk::field_problem(std::streamoff field_at, const std::string& problem) const {
    return "the data set's FIELD section (line " + std::to_string(line_of(path_, field_at)) +
           ") cannot be read: " + problem;
}

bool DataSetWalk::too_many(vtkIdType tuples, vtkIdType components) const {
    return tuples < 0 || components < 0 || (components > 0 && tuples > limit_ / components);
}

vtkSmartPointer<vtkAbstractArray> DataSetWalk::read_array(const std::string& what, const char* type,
                                                          vtkIdType tuples, vtkIdType components,
                                                          bool numeric, std::string& problem) {
    if (too_many(tuples, components)) {
        problem = what + ": " + std::to_string(tuples) + " tuples of " +
                  std::to_string(components) + " components, more than the file holds";
        return nullptr;
    }
    problem = string_values_problem(*reader_, type, tuples * components, file_size_);
    if (!problem.empty()) {
        problem = what + ": " + problem;
        return nullptr;
    }
    messages_.clear();
    auto array = vtk::TakeSmartPointer(reader_->ReadArray(type, tuples, components));
    if (!array || messages_.has_error())
        problem = what + " (" + std::to_string(tuples) + " tuples of " +
                  std::to_string(components) + " " + type +
                  "): " + (messages_.has_error() ? messages_.first_error() : "VTK cannot read it");
    else if (numeric && !vtkDataArray::SafeDownCast(array))
        problem = what + ": " + io::quoted(type) + " is not a numeric type";
    return problem.empty() ? array : nullptr;
}

vtkSmartPointer<vtkAbstractArray> DataSetWalk::read_array(const std::string& what, vtkIdType tuples,
                                                          vtkIdType components, bool numeric,
                                                          std::string& problem) {
    char type[256];
    if (reader_->ReadString(type))
        return read_array(what, type, tuples, components, numeric, problem);
    problem = what + ": the file ends before its data type";
    return nullptr;
}

std::string DataSetWalk::points(const std::string& word) {
    if (!reader_->Read(&points_)) return word + " has no point count";
    const std::string what = word + " " + std::to_string(points_);
    if (too_many(points_, 3)) return what + ": more points than the file holds";
    std::string problem;
    read_array(what, points_, 3, true, problem);
    return problem;
}

std::string DataSetWalk::cell_array(const std::string& word, vtkIdType& cells) {
    vtkIdType first = 0, second = 0;
    if (!reader_->Read(&first) || !reader_->Read(&second))
        return word + " has no cell count and size";
    const std::string what = word + " " + std::to_string(first) + " " + std::to_string(second);
    if (first < 0 || second < 0 || first > limit_ || second > limit_)
        return what + ": more than the file holds";
    if (major_version() < 5) {
        // "WORD cells size", then size integers: a count and that many ids for each cell.
        std::vector<int> values(static_cast<size_t>(second));
        if (!reader_->ReadCellsLegacy(second, values.data()))
            return what + ": the file ends, or has a word that is not an integer, in its " +
                   std::to_string(second) + " numbers";
        VectorInts ints{values};
        cells = first;
        return walk_cells(ints, word, first, second);
    }
    // "WORD offsets connectivity", then "OFFSETS type" and "CONNECTIVITY type" arrays.
    if (first < 1) return ""; // VTK reads no arrays
    cells = first - 1;
    std::string problem;
    char header[256];
    if (!reader_->ReadString(header) || lower(header) != "offsets")
        return what + ": no OFFSETS array";
    const auto offsets_array = read_array(what + " OFFSETS", first, 1, true, problem);
    auto* offsets = vtkDataArray::SafeDownCast(offsets_array);
    if (!offsets) return problem;
    if (!reader_->ReadString(header) || lower(header) != "connectivity")
        return what + ": no CONNECTIVITY array";
    const auto connectivity_array = read_array(what + " CONNECTIVITY", second, 1, true, problem);
    auto* connectivity = vtkDataArray::SafeDownCast(connectivity_array);
    if (!connectivity) return problem;
    messages_.clear();
    if (!vtkSmartPointer<vtkCellArray>::New()->SetData(offsets, connectivity))
        return what + ": " +
               (messages_.has_error() ? messages_.first_error()
                                      : "VTK takes no cells of these array types");
    // VTK does not check the offsets, and a cell past the connectivity is read past it.
    double before = 0;
    for (vtkIdType i = 0; i < first; ++i) {
        const double offset = offsets->GetComponent(i, 0);
        if ((i == 0 && offset != 0) || offset < before || offset > double(second))
            return what + ": offset " + std::to_string(i) + " is " + number(offset) +
                   " (offsets go from 0 up to the " + std::to_string(second) +
                   " ids of the connectivity)";
        before = offset;
    }
    if (before != double(second))
        return what + ": the offsets end at " + number(before) + ", not at the " +
               std::to_string(second) + " ids of the connectivity";
    return "";
}

std::string DataSetWalk::number(double value) {
    std::ostringstream out;
    out << value;
    return out.str();
}

std::string DataSetWalk::cell_types(const std::string& word) {
    vtkIdType count = 0;
    if (!reader_->Read(&count)) return word + " has no count";
    const std::string what = word + " " + std::to_string(count);
    if (types_) return "a second " + word + " section";
    if (count < 0 || count > limit_) return what + ": more types than the file holds";
    std::istream& in = *reader_->GetIStream();
    if (reader_->GetFileType() == VTK_BINARY) {
        char rest[256];
        in.getline(rest, 256); // as VTK reads them
        std::vector<char> bytes(sizeof(int) * size_t(count));
        in.read(bytes.data(), std::streamsize(bytes.size()));
        if (in.eof()) return what + ": the file ends in its types";
    } else {
        for (vtkIdType i = 0; i < count; ++i) {
            int type = 0;
            if (!reader_->Read(&type))
                return what + ": type " + std::to_string(i) +
                       " is not an integer, or the file ends before it";
        }
    }
    types_ = count;
    last_count_ = count;
    return "";
}

std::string DataSetWalk::types_for_cells() const {
    if (!types_ || !grid_cells_ || *types_ >= *grid_cells_) return "";
    return "CELL_TYPES has " + std::to_string(*types_) + " types for the " +
           std::to_string(*grid_cells_) + " cells of CELLS";
}

vtkIdType DataSetWalk::poly_cell_count() const {
    vtkIdType total = 0;
    for (const auto& [section, cells] : poly_cells_) total += cells;
    return total;
}

std::string DataSetWalk::data_count(const std::string& word, vtkIdType expected, const char* of,
                                    vtkIdType& count) const {
    const std::streamoff word_at = here();
    if (!reader_->Read(&count)) return at(word_at) + word + " has no count";
    if (count != expected)
        return at(word_at) + word + " " + std::to_string(count) + " for a data set of " +
               std::to_string(expected) + " " + of;
    return "";
}

} // namespace ddsimp::io::legacy_vtk

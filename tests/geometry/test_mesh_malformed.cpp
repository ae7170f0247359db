// Malformed mesh files: each gives a one-line inhap::Error naming the file, the line (or the
// binary element and record) and what was expected; seeded mutations never crash the readers.
#include <gtest/gtest.h>

#include "inhap/core/error.hpp"
#include "inhap/core/random.hpp"
#include "inhap/geometry/mesh_io.hpp"
#include "inhap/geometry/obj.hpp"
#include "inhap/geometry/ply.hpp"
#include "mesh_test_util.hpp"
#include "support/temp_dir.hpp"

using namespace inhap;
using inhap::test::Bytes;

namespace test_mesh_malformed {

struct Case {
  std::string name;
  std::string file;  ///< file name (its extension picks the reader)
  std::string content;
  std::size_t line;      ///< expected line in "path:line: ", 0 for "path: " (binary or whole file)
  std::string expected;  ///< substring of the message
};

std::ostream& operator<<(std::ostream& os, const Case& c) {
  return os << c.name;
}

const std::string kAsciiHead = "ply\nformat ascii 1.0\n";
const std::string kXyz = "property float x\nproperty float y\nproperty float z\n";
const std::string kFace = "element face 1\nproperty list uchar int vertex_indices\n";
// Header of 3 vertices and 1 face: 9 lines, so the data starts on line 10.
const std::string kTriHead = kAsciiHead + "element vertex 3\n" + kXyz + kFace + "end_header\n";
const std::string kVerts = "0.000 0.000 0.000\n1.000 0.000 0.000\n0.000 1.000 0.000\n";

std::string binary_tri(bool truncate_face) {
  Bytes b(false);
  b.text("ply\nformat binary_little_endian 1.0\nelement vertex 3\n" + kXyz + "element face 2\n" +
         "property list uchar int vertex_indices\nend_header\n");
  for (float v : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) b.put<float>(v);
  b.put<std::uint8_t>(3).put<std::int32_t>(0).put<std::int32_t>(1).put<std::int32_t>(2);
  b.put<std::uint8_t>(3).put<std::int32_t>(0);
  if (!truncate_face) b.put<std::int32_t>(2).put<std::int32_t>(1);
  return b.str();
}

std::vector<Case> cases() {
  const float inf = std::numeric_limits<float>::infinity();
  Bytes huge(false), trunc_scalar(false), inf_bin(true);
  huge.text("ply\nformat binary_little_endian 1.0\nelement vertex 1000000000\n" + kXyz +
            "end_header\n")
      .put<float>(1)
      .put<float>(2)
      .put<float>(3);
  trunc_scalar
      .text(
          "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty list uchar float uv\n" +
          kXyz + "end_header\n")
      .put<std::uint8_t>(0)
      .put<float>(1)
      .put<float>(2)
      .put<float>(3)
      .put<std::uint8_t>(1)
      .put<float>(9)
      .put<float>(1)
      .put<float>(2)
      .put<float>(3);
  inf_bin.text("ply\nformat binary_big_endian 1.0\nelement vertex 1\n" + kXyz + "end_header\n")
      .put<float>(1)
      .put<float>(inf)
      .put<float>(3);
  return {
      {"empty_file", "e.ply", "", 1, "expected 'ply' magic, got an empty file"},
      {"missing_magic", "m.ply", "plyx\nformat ascii 1.0\n", 1, "expected 'ply' magic, got 'plyx'"},
      {"bad_format_version", "f.ply", "ply\nformat ascii 2.0\n", 2,
       "expected format version 1.0, got '2.0'"},
      {"unknown_format", "f.ply", "ply\nformat binary_middle_endian 1.0\n", 2,
       "expected format ascii, binary_little_endian or binary_big_endian, got "
       "'binary_middle_endian'"},
      {"format_line_too_short", "f.ply", "ply\nformat ascii\n", 2, "expected 'format <ascii|"},
      {"unknown_header_keyword", "k.ply", kAsciiHead + "elemnt vertex 3\n", 3,
       "expected comment, obj_info, format, element, property or end_header, got 'elemnt'"},
      {"unknown_property_type", "t.ply", kAsciiHead + "element vertex 1\nproperty int64 x\n", 4,
       "expected a property type (char, uchar"},
      {"float_list_count", "t.ply", kAsciiHead + "element vertex 1\nproperty list float int x\n", 4,
       "expected an integer list count type, got 'float'"},
      {"property_before_element", "p.ply", kAsciiHead + "property float x\n", 3,
       "expected an 'element' line before the first property"},
      {"bad_element_count", "c.ply", kAsciiHead + "element vertex -3\n", 3,
       "expected a non-negative element count, got '-3'"},
      {"missing_end_header", "h.ply", kAsciiHead + "element vertex 1\n" + kXyz, 6,
       "expected 'end_header', got end of file"},
      {"missing_format", "h.ply", "ply\nelement vertex 0\n" + kXyz + "end_header\n", 6,
       "expected a 'format' line before end_header"},
      {"count_over_index_limit", "n.ply",
       kAsciiHead + "element vertex 1000000000000\n" + kXyz + "end_header\n1 2 3\n", 3,
       "expected at most 2147483647 vertex records, got 1000000000000"},
      {"count_too_big_binary", "n.ply", huge.str(), 3,
       "expected at most 12 bytes of data, but element 'vertex' declares 1000000000 records of at "
       "least 12 bytes"},
      {"count_too_big_ascii", "n.ply",
       kAsciiHead + "element vertex 2000000000\n" + kXyz + "end_header\n1 2 3\n", 3,
       "but element 'vertex' declares 2000000000 records of 3 values"},
      {"truncated_binary_list", "b.ply", binary_tri(true), 0,
       "element 'face' record 1, property 'vertex_indices': expected 3 list items of 4 bytes, got "
       "only 4 bytes"},
      {"truncated_binary_scalar", "b.ply",
       trunc_scalar.str().substr(0, trunc_scalar.str().size() - 2), 0,
       "element 'vertex' record 1, property 'z': expected 4 more bytes, got end of file"},
      {"binary_infinite_coordinate", "i.ply", inf_bin.str(), 0,
       "element 'vertex' record 0, property 'y': expected a finite number, got inf"},
      {"truncated_ascii_record", "a.ply",
       kTriHead + "0.000 0.000 0.000\n1.000 0.000 0.000\n0.000 1.000\n", 12,
       "element 'vertex' record 2, property 'z': expected a float value, got end of line"},
      {"truncated_ascii_element", "a.ply", kTriHead + kVerts, 12,
       "element 'face' record 0: expected a line with the record's values, got end of file"},
      {"non_number", "a.ply", kTriHead + "0 0 0\n1 abc 0\n0 1 0\n3 0 1 2\n", 11,
       "element 'vertex' record 1, property 'y': expected a float number, got 'abc'"},
      {"extra_value", "a.ply", kTriHead + "0 0 0 5\n1 0 0\n0 1 0\n3 0 1 2\n", 10,
       "element 'vertex' record 0: expected end of line after 3 properties, got '5'"},
      {"trailing_data", "a.ply", kTriHead + kVerts + "3 0 1 2\n3 0 1 2\n", 14,
       "expected end of file after the last element, got '3'"},
      {"nan_coordinate", "a.ply", kTriHead + "nan 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", 10,
       "property 'x': expected a finite number, got nan"},
      {"index_out_of_range", "a.ply", kTriHead + kVerts + "3 0 1 7\n", 13,
       "property 'vertex_indices': expected a vertex index in [0, 3), got 7"},
      {"negative_index", "a.ply", kTriHead + kVerts + "3 0 -1 2\n", 13,
       "expected a non-negative vertex index, got -1"},
      {"count_out_of_type_range", "a.ply", kTriHead + kVerts + "300 0 1 2\n", 13,
       "expected an integer of type uchar in [0, 255], got '300'"},
      {"face_two_vertices", "a.ply", kTriHead + kVerts + "2 0 1\n", 13,
       "expected at least 3 vertex indices, got 2"},
      {"face_repeated_vertex", "a.ply", kTriHead + kVerts + "3 0 1 0\n", 13,
       "expected at least 3 distinct vertices, got 2"},
      {"x_declared_as_list", "l.ply",
       kAsciiHead + "element vertex 1\nproperty list uchar float x\n" +
           "property float y\nproperty float z\nend_header\n1 0 0 0\n",
       4, "property 'x' of element 'vertex': expected a scalar, got a list"},
      {"face_without_list", "l.ply",
       kAsciiHead + "element vertex 3\n" + kXyz +
           "element face 1\nproperty int vertex_indices\nend_header\n" + kVerts + "0\n",
       8, "property 'vertex_indices' of element 'face': expected a list, got a scalar int"},
      {"face_float_indices", "l.ply",
       kAsciiHead + "element vertex 3\n" + kXyz +
           "element face 1\nproperty list uchar float vertex_indices\nend_header\n" + kVerts +
           "3 0 1 2\n",
       8, "expected an integer index type, got float"},
      {"face_no_index_list", "l.ply",
       kAsciiHead + "element vertex 3\n" + kXyz +
           "element face 1\nproperty uchar flags\nend_header\n" + kVerts + "0\n",
       7, "element 'face': expected a list property 'vertex_indices' or 'vertex_index', got none"},
      {"missing_y", "y.ply",
       kAsciiHead + "element vertex 1\nproperty float x\nproperty float z\nend_header\n0 0\n", 3,
       "element 'vertex': expected a scalar property 'y', got none"},
      {"no_vertex_element", "v.ply",
       kAsciiHead + "element point 1\nproperty float x\nend_header\n0\n", 5,
       "expected an 'element vertex' in the header, got none"},
      {"duplicate_property", "d.ply",
       kAsciiHead + "element vertex 1\n" + kXyz + "property float x\n", 7,
       "expected distinct property names in element 'vertex', got 'x' twice"},
      {"obj_bad_index", "o.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 x 3\n", 4,
       "f: expected a vertex reference v, v/vt, v//vn or v/vt/vn, got 'x'"},
      {"obj_non_number", "o.obj", "v 0 0 0\nv 1 abc 0\n", 2,
       "v: expected a number for y, got 'abc'"},
      {"obj_too_few_coordinates", "o.obj", "v 0 0\n", 1, "v: expected 3 coordinates, got 2 (no z)"},
      {"obj_nan", "o.obj", "v 0 nan 0\n", 1, "v: expected a finite y, got 'nan'"},
      {"obj_missing_vertex", "o.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 9\n", 5,
       "face: expected vertex indices up to 3 (the file's vertex count), got 9"},
      {"obj_zero_index", "o.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", 4,
       "f: expected a non-zero vertex index (OBJ counts from 1), got '0'"},
      {"obj_relative_too_far", "o.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n", 4,
       "f: expected a relative index from -1 to -3 (vertices so far), got -4"},
      {"obj_two_vertex_face", "o.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n", 3,
       "f: expected at least 3 vertices, got 2"},
      {"obj_garbage", "o.obj", "v 0 0 0\n\x01\x02 3\n", 2,
       "expected an OBJ statement (v, f, vn, vt, o, g, s, usemtl, ...), got '\\x01\\x02'"},
      {"obj_empty", "o.obj", "", 0, "expected at least one 'v' line, got none"},
      {"unknown_extension", "mesh.stl", "solid x\n", 0,
       "expected a mesh file ending in .ply or .obj, got '.stl'"},
  };
}

class MalformedMesh : public ::testing::TestWithParam<Case> {};

TEST_P(MalformedMesh, GivesOneLineErrorWithFileLineAndExpectation) {
  const Case& c = GetParam();
  test::TempDir dir;
  const std::string path = test::write_bytes(dir.path(c.file), c.content);
  std::string msg;
  try {
    read_mesh(path);
    FAIL() << "no error for " << c.name;
  } catch (const Error& e) {
    msg = e.what();
  } catch (const std::exception& e) {
    FAIL() << "not an inhap::Error: " << e.what();
  }
  const std::string prefix = c.line ? path + ":" + std::to_string(c.line) + ": " : path + ": ";
  EXPECT_EQ(msg.rfind(prefix, 0), 0u) << "expected prefix '" << prefix << "' in: " << msg;
  EXPECT_NE(msg.find(c.expected), std::string::npos)
      << "expected '" << c.expected << "' in: " << msg;
  EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  EXPECT_LT(msg.size(), 400u) << msg;
}

INSTANTIATE_TEST_SUITE_P(Cases, MalformedMesh, ::testing::ValuesIn(cases()),
                         [](const auto& param_info) { return param_info.param.name; });

// ---------------------------------------------------------------------------------------------
// Mutation fuzzing: ~2000 seeded mutations of valid files; every read either returns a valid
// mesh or throws inhap::Error.
std::string mutate(std::string s, Rng& rng) {
  const auto n = s.size();
  switch (rng.below(6)) {
    case 0:  // overwrite 1..8 random bytes
      for (std::uint64_t k = 0, m = 1 + rng.below(8); k < m && n; ++k)
        s[rng.below(n)] = static_cast<char>(rng.below(256));
      break;
    case 1:  // truncate
      s.resize(rng.below(n + 1));
      break;
    case 2: {  // plausible text bytes: digits, signs, separators, letters
      static const char kChars[] = "0123456789-+. \n\te/nanif";
      for (std::uint64_t k = 0, m = 1 + rng.below(4); k < m && n; ++k)
        s[rng.below(n)] = kChars[rng.below(sizeof(kChars) - 1)];
      break;
    }
    case 3: {  // delete a span
      const auto at = rng.below(n + 1);
      s.erase(at, rng.below(16));
      break;
    }
    case 4: {  // duplicate a span
      const auto at = rng.below(n + 1);
      s.insert(at, s.substr(at, rng.below(32)));
      break;
    }
    default: {  // grow a decimal number (counts in headers, indices)
      std::vector<std::size_t> digits;
      for (std::size_t i = 0; i < n; ++i)
        if (s[i] >= '0' && s[i] <= '9') digits.push_back(i);
      if (!digits.empty())
        s.insert(digits[rng.below(digits.size())], std::string(1 + rng.below(12), '9'));
      break;
    }
  }
  return s;
}

TEST(MeshFuzz, SeededMutationsEitherReadValidMeshesOrThrowInhapError) {
  const TriMesh base = test::awkward_mesh();
  std::string obj = format_obj(base) + "vn 0 0 1\nvt 0 1\nf 1/1/1 2//1 -1/1\ng x\nf -4 -3 -2 -1\n";
  const std::vector<std::pair<std::string, bool>> files = {
      {format_ply(base, {PlyFormat::kBinaryLittleEndian}), true},
      {format_ply(base, {PlyFormat::kBinaryBigEndian}), true},
      {format_ply(base, {PlyFormat::kAscii}), true},
      {obj, false},
  };
  int ok = 0, errors = 0;
  for (std::size_t f = 0; f < files.size(); ++f) {
    for (int i = 0; i < 500; ++i) {
      Rng rng(1000 * (f + 1) + i);
      std::string bytes = mutate(files[f].first, rng);
      if (rng.below(4) == 0) bytes = mutate(bytes, rng);  // sometimes two mutations
      try {
        const TriMesh m =
            files[f].second ? parse_ply(bytes, "fuzz.ply") : parse_obj(bytes, "fuzz.obj");
        EXPECT_NO_THROW(m.validate("fuzz"));
        EXPECT_EQ(m.normals.size(), m.positions.size());
        ++ok;
      } catch (const Error& e) {
        const std::string msg = e.what();
        EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
        ++errors;
      } catch (const std::exception& e) {
        ADD_FAILURE() << "file " << f << " seed " << i << ": not an inhap::Error: " << e.what();
      }
    }
  }
  // Both outcomes must occur, or the mutations are not exercising the readers.
  EXPECT_GT(ok, 100);
  EXPECT_GT(errors, 100);
  std::printf("fuzz: %d read fine, %d rejected with inhap::Error\n", ok, errors);
}

}  // namespace test_mesh_malformed

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <tuple>

#include "inhap/core/atomic_file.hpp"
#include "inhap/core/error.hpp"
#include "inhap/geometry/mesh_io.hpp"
#include "inhap/geometry/ply.hpp"
#include "mesh_test_util.hpp"
#include "support/temp_dir.hpp"

using namespace inhap;
using inhap::test::Bytes;

namespace {

const char* format_line(PlyFormat f) {
  return f == PlyFormat::kAscii                ? "format ascii 1.0\n"
         : f == PlyFormat::kBinaryLittleEndian ? "format binary_little_endian 1.0\n"
                                               : "format binary_big_endian 1.0\n";
}

// The five vertices and faces every hand-written file below encodes: a unit square (quad) in
// z = 0 and a triangle beside it, all counter-clockwise seen from +z.
const std::vector<Vec3> kPositions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0),
                                      Vec3(2, 0.5, 0)};
const std::vector<Tri> kTriangles = {{0, 1, 2}, {0, 2, 3}, {1, 4, 2}};

void expect_hand_written_mesh(const TriMesh& m) {
  ASSERT_EQ(m.positions, kPositions);
  EXPECT_EQ(m.triangles, kTriangles);
  // Properties: `flags` (ushort) and `intensity` (double) kept; lists never become properties.
  ASSERT_TRUE(m.has_property("flags"));
  ASSERT_TRUE(m.has_property("intensity"));
  EXPECT_EQ(m.properties.size(), 2u);
  EXPECT_EQ(m.property("flags"), (std::vector<double>{0, 1, 65535, 3, 4}));
  EXPECT_EQ(m.property("intensity"), (std::vector<double>{0.5, -0.25, 1e-3, 4, 1e10}));
  // No normals in the file: computed, and all +z for this flat CCW mesh.
  ASSERT_EQ(m.normals.size(), 5u);
  for (const auto& n : m.normals) EXPECT_LT((n - Vec3(0, 0, 1)).norm(), 1e-12);
}

}  // namespace

// ---------------------------------------------------------------------------------------------
class PlyRoundTrip : public ::testing::TestWithParam<PlyFormat> {};

TEST_P(PlyRoundTrip, IsBitExactWithNormalsAndProperties) {
  test::TempDir dir;
  const TriMesh m = test::awkward_mesh();
  const std::string path = dir.path("m.ply");
  write_ply(path, m, {GetParam()});
  const std::string bytes = read_file(path);
  EXPECT_EQ(bytes.find(std::string("ply\n") + format_line(GetParam())), 0u);
  EXPECT_NE(bytes.find("comment written by inhap; units: positions mm, stiffness N/mm\n"),
            std::string::npos);
  EXPECT_NE(bytes.find("property double stiffness\n"), std::string::npos);
  EXPECT_NE(bytes.find("property list uchar int vertex_indices\n"), std::string::npos);
  const TriMesh back = read_ply(path);
  EXPECT_TRUE(test::bit_identical(m, back));
  EXPECT_EQ(std::signbit(back.positions[0].z()), true);  // -0.0 survives
  // Atomic write: only the final file is left in the folder.
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir.root()), {}), 1);
}

INSTANTIATE_TEST_SUITE_P(Formats, PlyRoundTrip,
                         ::testing::Values(PlyFormat::kAscii, PlyFormat::kBinaryLittleEndian,
                                           PlyFormat::kBinaryBigEndian),
                         [](const auto& param_info) {
                           return std::string(param_info.param == PlyFormat::kAscii ? "ascii"
                                              : param_info.param == PlyFormat::kBinaryLittleEndian
                                                  ? "binary_le"
                                                  : "binary_be");
                         });

TEST(PlyWrite, BinaryBodyHasExactSizeAndLayout) {
  // 4 vertices x (3 + 3 + 3) doubles + 2 faces x (1 + 3 * 4) bytes after the header.
  const TriMesh m = test::awkward_mesh();
  const std::string bytes = format_ply(m);
  const auto body = bytes.size() - (bytes.find("end_header\n") + 11);
  EXPECT_EQ(body, 4u * 9 * 8 + 2u * 13);
}

TEST(PlyWrite, UnwritableTargetsAndNamesThrowAndLeaveNoFile) {
  test::TempDir dir;
  TriMesh m = test::awkward_mesh();
  EXPECT_THROW(write_ply(dir.path("missing/m.ply"), m), IoError);
  m.properties["two words"] = {1, 2, 3, 4};
  try {
    write_ply(dir.path("m.ply"), m);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("'two words'"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(dir.path("m.ply")));
  m.properties.erase("two words");
  m.triangles.push_back({0, 1, 9});  // invalid mesh: refused before anything is written
  EXPECT_THROW(write_ply(dir.path("m.ply"), m), Error);
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir.root()), {}), 0);
}

// ---------------------------------------------------------------------------------------------
// Hand-written binary files: every count/index type pair, an `edge` element before the faces,
// a `material` element with a list after them, a vertex list property, a face scalar and a
// face list besides vertex_indices.
struct TypePair {
  const char* count;
  const char* index;
};

class PlyHandWrittenBinary : public ::testing::TestWithParam<std::tuple<bool, TypePair>> {};

template <class C, class I>
void put_face(Bytes& b, std::initializer_list<int> idx) {
  b.put<std::uint8_t>(7);  // `material` scalar before the list
  b.put<C>(static_cast<C>(idx.size()));
  for (int i : idx) b.put<I>(static_cast<I>(i));
  b.put<std::uint8_t>(2).put<float>(0.5f).put<float>(0.25f);  // `uv` list after it
}

template <class C, class I>
std::string hand_written(bool big, const TypePair& tp) {
  Bytes b(big);
  b.text(std::string("ply\n") +
         (big ? "format binary_big_endian 1.0\n" : "format binary_little_endian 1.0\n"));
  b.text(
      "comment hand-written\nobj_info test\nelement vertex 5\nproperty float x\nproperty float "
      "y\n");
  b.text(
      "property float z\nproperty list uchar float texcoord\nproperty ushort flags\nproperty "
      "double intensity\n");
  b.text("element edge 2\nproperty int vertex1\nproperty int vertex2\nproperty uchar red\n");
  b.text(std::string("element face 2\nproperty uchar material\nproperty list ") + tp.count + " " +
         tp.index + " vertex_indices\nproperty list uchar float uv\n");
  b.text("element material 1\nproperty list uint char name\nend_header\n");
  const double intensity[] = {0.5, -0.25, 1e-3, 4, 1e10};
  const std::uint16_t flags[] = {0, 1, 65535, 3, 4};
  for (int v = 0; v < 5; ++v) {
    for (int c = 0; c < 3; ++c) b.put<float>(static_cast<float>(kPositions[v][c]));
    b.put<std::uint8_t>(static_cast<std::uint8_t>(v % 3));  // texcoord list of v % 3 floats
    for (int k = 0; k < v % 3; ++k) b.put<float>(1.5f);
    b.put<std::uint16_t>(flags[v]).put<double>(intensity[v]);
  }
  b.put<std::int32_t>(0).put<std::int32_t>(1).put<std::uint8_t>(255);
  b.put<std::int32_t>(1).put<std::int32_t>(2).put<std::uint8_t>(0);
  put_face<C, I>(b, {0, 1, 2, 3});
  put_face<C, I>(b, {1, 4, 2});
  b.put<std::uint32_t>(3).text("abc");
  return b.str();
}

std::string hand_written(bool big, const TypePair& tp) {
  const std::string c = tp.count, i = tp.index;
  if (c == "uchar" && i == "int") return hand_written<std::uint8_t, std::int32_t>(big, tp);
  if (c == "uchar" && i == "uchar") return hand_written<std::uint8_t, std::uint8_t>(big, tp);
  if (c == "ushort" && i == "ushort") return hand_written<std::uint16_t, std::uint16_t>(big, tp);
  if (c == "int8" && i == "int16") return hand_written<std::int8_t, std::int16_t>(big, tp);
  if (c == "uint" && i == "uint32") return hand_written<std::uint32_t, std::uint32_t>(big, tp);
  if (c == "uint16" && i == "char") return hand_written<std::uint16_t, std::int8_t>(big, tp);
  throw std::logic_error("unknown type pair");
}

TEST_P(PlyHandWrittenBinary, ReadsExpectedTrianglesAndProperties) {
  const auto [big, tp] = GetParam();
  test::TempDir dir;
  const auto path = test::write_bytes(dir.path("hand.ply"), hand_written(big, tp));
  expect_hand_written_mesh(read_ply(path));
}

INSTANTIATE_TEST_SUITE_P(
    Types, PlyHandWrittenBinary,
    ::testing::Combine(::testing::Bool(),
                       ::testing::Values(TypePair{"uchar", "int"}, TypePair{"uchar", "uchar"},
                                         TypePair{"ushort", "ushort"}, TypePair{"int8", "int16"},
                                         TypePair{"uint", "uint32"}, TypePair{"uint16", "char"})),
    [](const auto& param_info) {
      const TypePair& tp = std::get<1>(param_info.param);
      return std::string(std::get<0>(param_info.param) ? "be_" : "le_") + tp.count + "_" + tp.index;
    });

TEST(PlyRead, HandWrittenAsciiWithCrlfAndVertexIndexName) {
  std::string text =
      "ply\nformat ascii 1.0\ncomment made by hand\nobj_info nothing\nelement vertex 5\n"
      "property float x\nproperty float y\nproperty float z\nproperty list uchar float texcoord\n"
      "property ushort flags\nproperty double intensity\nelement edge 2\nproperty int vertex1\n"
      "property int vertex2\nelement face 2\nproperty list uchar int vertex_index\n"
      "property uchar material\nelement material 1\nproperty list uint char name\nend_header\n"
      "0 0 0 0 0 0.5\n1 0 0 1 1.5 1 -0.25\n1 1 0 2 1.5 1.5 65535 1e-3\n+0 1 0 0 3 4\n"
      "2 0.5 0 1 1.5 4 1e10\n0 1\n1 2\n4 0 1 2 3 7\n3 1 4 2 7\n\n3 97 98 99\n\n";
  std::string crlf;
  for (char c : text) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
  test::TempDir dir;
  expect_hand_written_mesh(read_ply(test::write_bytes(dir.path("lf.ply"), text)));
  expect_hand_written_mesh(read_ply(test::write_bytes(dir.path("crlf.ply"), crlf)));
}

TEST(PlyRead, PolygonsWithConsecutiveRepeatsAreCollapsedBeforeFanning) {
  // "4 0 1 2 2" is the triangle 0 1 2 written as a quad; "5 0 0 1 2 3" is the quad 0 1 2 3.
  const std::string text =
      "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float "
      "z\n"
      "element face 2\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 2\n5 0 0 1 2 3\n";
  const TriMesh m = parse_ply(text, "mem");
  EXPECT_EQ(m.triangles, (std::vector<Tri>{{0, 1, 2}, {0, 1, 2}, {0, 2, 3}}));
}

// ---------------------------------------------------------------------------------------------
class PlyVertexType : public ::testing::TestWithParam<const char*> {};

TEST_P(PlyVertexType, AnyNumericTypeForCoordinates) {
  const std::string t = GetParam();
  const std::string header =
      "element vertex 3\nproperty " + t + " x\nproperty " + t + " y\nproperty " + t +
      " z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  const TriMesh a =
      parse_ply("ply\nformat ascii 1.0\n" + header + "7 0 1\n0 7 1\n0 0 1\n3 0 1 2\n", "a");
  const std::vector<Vec3> expected = {Vec3(7, 0, 1), Vec3(0, 7, 1), Vec3(0, 0, 1)};
  EXPECT_EQ(a.positions, expected);
  // Same values in binary: write each coordinate with the declared type's size.
  Bytes b(false);
  b.text("ply\nformat binary_little_endian 1.0\n" + header);
  for (const auto& p : expected)
    for (int c = 0; c < 3; ++c) {
      const auto v = static_cast<int>(p[c]);
      if (t == "char" || t == "int8")
        b.put<std::int8_t>(static_cast<std::int8_t>(v));
      else if (t == "uchar" || t == "uint8")
        b.put<std::uint8_t>(static_cast<std::uint8_t>(v));
      else if (t == "short" || t == "int16")
        b.put<std::int16_t>(static_cast<std::int16_t>(v));
      else if (t == "ushort" || t == "uint16")
        b.put<std::uint16_t>(static_cast<std::uint16_t>(v));
      else if (t == "int" || t == "int32")
        b.put<std::int32_t>(v);
      else if (t == "uint" || t == "uint32")
        b.put<std::uint32_t>(static_cast<std::uint32_t>(v));
      else if (t == "float" || t == "float32")
        b.put<float>(static_cast<float>(v));
      else
        b.put<double>(v);
    }
  b.put<std::uint8_t>(3).put<std::int32_t>(0).put<std::int32_t>(1).put<std::int32_t>(2);
  EXPECT_EQ(parse_ply(b.str(), "b").positions, expected);
}

INSTANTIATE_TEST_SUITE_P(AllNames, PlyVertexType,
                         ::testing::Values("char", "uchar", "short", "ushort", "int", "uint",
                                           "float", "double", "int8", "uint8", "int16", "uint16",
                                           "int32", "uint32", "float32", "float64"));

TEST(PlyRead, NormalsComeFromTheFileNotRecomputed) {
  // Geometry faces +z but the file says -z: the file wins.
  const std::string text =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float "
      "z\n"
      "property float nx\nproperty float ny\nproperty float nz\nproperty float stiffness\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0 0 0 -1 0.5\n1 0 0 0 0 -1 0.25\n0 1 0 0 0 -1 2\n3 0 1 2\n";
  const TriMesh m = parse_ply(text, "mem");
  ASSERT_EQ(m.normals.size(), 3u);
  for (const auto& n : m.normals) EXPECT_EQ(n, Vec3(0, 0, -1));
  EXPECT_EQ(m.properties.size(), 1u);  // nx/ny/nz are normals, not properties
  EXPECT_EQ(m.property("stiffness"), (std::vector<double>{0.5, 0.25, 2}));
}

TEST(PlyRead, AsciiFloatEqualsBinaryFloatAndDoubleIsExact) {
  const std::string text =
      "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty double y\nproperty "
      "float z\n"
      "end_header\n0.1 0.1 1e-3\n";
  const TriMesh m = parse_ply(text, "mem");
  EXPECT_EQ(m.positions[0].x(), static_cast<double>(0.1f));
  EXPECT_EQ(m.positions[0].y(), 0.1);
  EXPECT_EQ(m.positions[0].z(), static_cast<double>(1e-3f));
  EXPECT_TRUE(m.triangles.empty());  // a point cloud without faces is allowed
}

TEST(PlyRead, HugeElementWithoutPropertiesIsSkippedInstantly) {
  const std::string text =
      "ply\nformat binary_little_endian 1.0\nelement marker 1000000000000\nelement vertex 0\n"
      "property float x\nproperty float y\nproperty float z\nend_header\n";
  EXPECT_EQ(parse_ply(text, "mem").num_vertices(), 0u);
}

// ---------------------------------------------------------------------------------------------
TEST(PlyBunny, RealStanfordBunnyHasKnownCountsAndProperties) {
  const std::string path = test::shared_data("bunny/bun_zipper.ply");
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "absent: " << path;
  const TriMesh m = read_mesh(path);
  EXPECT_EQ(m.num_vertices(), 35947u);
  EXPECT_EQ(m.num_triangles(), 69451u);
  EXPECT_EQ(m.normals.size(), m.num_vertices());
  const auto& conf = m.property("confidence");
  EXPECT_GE(*std::min_element(conf.begin(), conf.end()), 0.0);
  const double cmax = *std::max_element(conf.begin(), conf.end());
  EXPECT_GE(cmax, 0.999);
  EXPECT_LE(cmax, 0.9994);
  const auto& inten = m.property("intensity");
  EXPECT_EQ(inten.size(), m.num_vertices());
  EXPECT_LE(*std::max_element(inten.begin(), inten.end()), 0.5);
  // Published bounding box of bun_zipper (metres, as stored).
  const Box3 b = m.bbox();
  EXPECT_NEAR(b.min.x(), -0.0946899, 1e-6);
  EXPECT_NEAR(b.max.x(), 0.0610091, 1e-6);
  EXPECT_NEAR(b.min.y(), 0.0329874, 1e-6);
  EXPECT_NEAR(b.max.y(), 0.187321, 1e-6);
  EXPECT_NEAR(b.min.z(), -0.0618736, 1e-6);
  EXPECT_NEAR(b.max.z(), 0.0587997, 1e-6);
  // Binary round trip keeps everything bit for bit.
  test::TempDir dir;
  EXPECT_TRUE(write_mesh(dir.path("bunny.ply"), m).empty());
  EXPECT_TRUE(test::bit_identical(m, read_mesh(dir.path("bunny.ply"))));
}

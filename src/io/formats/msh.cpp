#include "io/formats/msh.hpp"

#include "io/formats/atomic_file.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <istream>
#include <map>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <string_view>
#include <unordered_map>
#include <vector>

#include <Eigen/Geometry>

#include "fem/mesh_ops.hpp"

namespace codesign::io {
namespace {

using fem::TetMesh;
using fem::Tri;

// ---------------------------------------------------------------------------------------------
// Writing
// ---------------------------------------------------------------------------------------------

struct TaggedSurface {
  std::string name;
  const std::vector<Tri>* faces;
};

std::vector<TaggedSurface> surfaces_of(const TetMesh& m) {
  std::vector<TaggedSurface> s;
  if (!m.base_faces.empty()) s.push_back({"base", &m.base_faces});
  if (!m.tip_faces.empty()) s.push_back({"tip", &m.tip_faces});
  for (std::size_t c = 0; c < m.chamber_faces.size(); ++c) {
    if (!m.chamber_faces[c].empty()) s.push_back({"chamber_" + std::to_string(c + 1), &m.chamber_faces[c]});
  }
  return s;
}

void write_bbox(std::ostream& out, const TetMesh& m, const std::vector<int>& nodes) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
  for (int v : nodes) {
    lo = lo.cwiseMin(m.nodes[v]);
    hi = hi.cwiseMax(m.nodes[v]);
  }
  if (nodes.empty()) lo = hi = Eigen::Vector3d::Zero();
  char buf[160];
  std::snprintf(buf, sizeof buf, "%.17g %.17g %.17g %.17g %.17g %.17g", lo.x(), lo.y(), lo.z(), hi.x(), hi.y(), hi.z());
  out << buf;
}

// ---------------------------------------------------------------------------------------------
// Reading: a line-aware tokenizer that knows where every token came from.
// ---------------------------------------------------------------------------------------------

class Lexer {
 public:
  Lexer(std::istream& in, std::string label) : in_(in), label_(std::move(label)) {}

  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(label_ + ":" + std::to_string(line_) + ": " + what);
  }
  [[noreturn]] void expected(std::string_view what, std::string_view got) const {
    fail("expected " + std::string(what) + ", got " + (got.empty() ? std::string("end of file") : "'" + std::string(got) + "'"));
  }

  // The next token (crossing line ends); "" at end of file.
  std::string_view peek() {
    while (pos_ >= toks_.size()) {
      if (!load_line()) return {};
    }
    return toks_[pos_];
  }
  std::string_view next(std::string_view what) {
    const std::string_view t = peek();
    if (t.empty()) expected(what, t);
    ++pos_;
    return t;
  }
  long long integer(std::string_view what, long long lo, long long hi) {
    const std::string_view t = next(what);
    long long v = 0;
    const auto [p, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    if (ec != std::errc() || p != t.data() + t.size() || v < lo || v > hi) expected(what, t);
    return v;
  }
  double real(std::string_view what) {
    const std::string_view t = next(what);
    double v = 0;
    const auto [p, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    if (ec != std::errc() || p != t.data() + t.size()) expected(what, t);
    return v;
  }
  void keyword(std::string_view kw) {
    const std::string_view t = next(kw);
    if (t != kw) expected(kw, t);
  }
  // The rest of the current line (raw text after the last consumed token), and moves on.
  std::string rest_of_line() {
    std::string r;
    if (pos_ < toks_.size()) r = line_text_.substr(static_cast<std::size_t>(toks_[pos_].data() - line_text_.data()));
    pos_ = toks_.size();
    return r;
  }
  void skip_line() { pos_ = toks_.size(); }
  int line() const { return line_; }
  const std::string& label() const { return label_; }

 private:
  bool load_line() {
    if (!std::getline(in_, line_text_)) return false;
    ++line_;
    toks_.clear();
    pos_ = 0;
    const std::string_view s = line_text_;
    std::size_t i = 0;
    while (i < s.size()) {
      while (i < s.size() && (s[i] == ' ' || s[i] == '\t' || s[i] == '\r')) ++i;
      std::size_t j = i;
      while (j < s.size() && s[j] != ' ' && s[j] != '\t' && s[j] != '\r') ++j;
      if (j > i) toks_.push_back(s.substr(i, j - i));
      i = j;
    }
    return true;
  }

  std::istream& in_;
  std::string label_;
  std::string line_text_;
  std::vector<std::string_view> toks_;
  std::size_t pos_ = 0;
  int line_ = 0;
};

constexpr long long kMaxCount = 1LL << 31;
// Tags stored as int: at most INT_MAX, and physical tags (which may be negative in $Entities)
// at least -INT_MAX, so that std::abs of one is defined.
constexpr long long kMaxTag = 2147483647LL;

struct Entity {
  std::vector<int> physicals;
};

struct RawMesh {
  bool have_format = false;
  std::map<std::pair<int, int>, std::string> physical_names;  // (dim, tag) → name
  std::map<std::pair<int, int>, Entity> entities;             // (dim, tag) → physical tags
  std::vector<std::size_t> node_tags;
  std::vector<Eigen::Vector3d> nodes;
  std::vector<std::array<std::size_t, 4>> tets;
  std::vector<int> tet_lines;
  struct Face {
    std::array<std::size_t, 3> nodes;
    int entity;
    int line;
  };
  std::vector<Face> faces;
};

void read_format(Lexer& lx, RawMesh& raw) {
  const std::string_view version = lx.next("4.1 in $MeshFormat");
  if (version != "4.1") lx.expected("4.1 in $MeshFormat", version);
  const long long type = lx.integer("file type 0 (ASCII) in $MeshFormat", 0, 1);
  if (type != 0) lx.fail("expected file type 0 (ASCII) in $MeshFormat, got 1 (binary); save the mesh as ASCII");
  lx.integer("data size in $MeshFormat", 1, 16);
  lx.keyword("$EndMeshFormat");
  raw.have_format = true;
}

void read_physical_names(Lexer& lx, RawMesh& raw) {
  const long long n = lx.integer("number of physical names", 0, kMaxCount);
  for (long long i = 0; i < n; ++i) {
    const int dim = static_cast<int>(lx.integer("physical dimension 0..3", 0, 3));
    const int tag = static_cast<int>(lx.integer("physical tag", 1, kMaxTag));
    std::string name = lx.rest_of_line();
    while (!name.empty() && (name.back() == ' ' || name.back() == '\r' || name.back() == '\t')) name.pop_back();
    if (name.size() < 2 || name.front() != '"' || name.back() != '"') lx.expected("a quoted physical name", name);
    raw.physical_names[{dim, tag}] = name.substr(1, name.size() - 2);
  }
  lx.keyword("$EndPhysicalNames");
}

void read_entities(Lexer& lx, RawMesh& raw) {
  long long count[4];
  for (int d = 0; d < 4; ++d) count[d] = lx.integer("entity count in $Entities", 0, kMaxCount);
  for (int d = 0; d < 4; ++d) {
    for (long long i = 0; i < count[d]; ++i) {
      const int tag = static_cast<int>(lx.integer("entity tag", 1, kMaxTag));
      const int coords = d == 0 ? 3 : 6;
      for (int k = 0; k < coords; ++k) lx.real("entity coordinate");
      Entity e;
      const long long np = lx.integer("number of physical tags", 0, kMaxCount);
      for (long long k = 0; k < np; ++k) e.physicals.push_back(static_cast<int>(lx.integer("physical tag", -kMaxTag, kMaxTag)));
      if (d > 0) {
        const long long nb = lx.integer("number of bounding entities", 0, kMaxCount);
        for (long long k = 0; k < nb; ++k) lx.integer("bounding entity tag", -kMaxCount, kMaxCount);
      }
      raw.entities[{d, tag}] = std::move(e);
    }
  }
  lx.keyword("$EndEntities");
}

void read_nodes(Lexer& lx, RawMesh& raw) {
  const long long blocks = lx.integer("number of node blocks", 0, kMaxCount);
  const long long total = lx.integer("number of nodes", 0, kMaxCount);
  lx.integer("min node tag", 0, 1LL << 62);
  lx.integer("max node tag", 0, 1LL << 62);
  // (no reserve(total): the count is the file's claim, checked against the nodes actually read)
  for (long long b = 0; b < blocks; ++b) {
    const int dim = static_cast<int>(lx.integer("entity dimension 0..3", 0, 3));
    lx.integer("entity tag", 0, kMaxCount);
    const long long parametric = lx.integer("parametric flag 0 or 1", 0, 1);
    const long long n = lx.integer("number of nodes in block", 0, kMaxCount);
    for (long long i = 0; i < n; ++i) raw.node_tags.push_back(static_cast<std::size_t>(lx.integer("node tag", 1, 1LL << 62)));
    const int extra = (parametric && dim > 0 && dim < 3) ? dim : 0;
    for (long long i = 0; i < n; ++i) {
      Eigen::Vector3d p;
      for (int k = 0; k < 3; ++k) p[k] = lx.real("node coordinate");
      for (int k = 0; k < extra; ++k) lx.real("parametric node coordinate");
      if (!p.allFinite()) lx.fail("expected finite node coordinates");
      raw.nodes.push_back(p);
    }
  }
  if (static_cast<long long>(raw.nodes.size()) != total) {
    lx.fail("expected " + std::to_string(total) + " nodes as announced in $Nodes, got " + std::to_string(raw.nodes.size()));
  }
  lx.keyword("$EndNodes");
}

void read_elements(Lexer& lx, RawMesh& raw) {
  const long long blocks = lx.integer("number of element blocks", 0, kMaxCount);
  lx.integer("number of elements", 0, kMaxCount);
  lx.integer("min element tag", 0, 1LL << 62);
  lx.integer("max element tag", 0, 1LL << 62);
  for (long long b = 0; b < blocks; ++b) {
    const int dim = static_cast<int>(lx.integer("entity dimension 0..3", 0, 3));
    const int entity = static_cast<int>(lx.integer("entity tag", 0, kMaxTag));
    const long long type = lx.integer("element type", 1, 1000);
    const long long n = lx.integer("number of elements in block", 0, kMaxCount);
    if (dim == 3 && type != 4) {
      lx.fail("expected element type 4 (linear tetrahedron) in a volume block, got type " + std::to_string(type) +
              "; only linear tetrahedra are supported");
    }
    for (long long i = 0; i < n; ++i) {
      lx.integer("element tag", 1, 1LL << 62);
      if (type == 4) {
        std::array<std::size_t, 4> t;
        for (auto& v : t) v = static_cast<std::size_t>(lx.integer("node tag of a tetrahedron", 1, 1LL << 62));
        raw.tets.push_back(t);
        raw.tet_lines.push_back(lx.line());
      } else if (type == 2) {
        RawMesh::Face f{{}, entity, 0};
        for (auto& v : f.nodes) v = static_cast<std::size_t>(lx.integer("node tag of a triangle", 1, 1LL << 62));
        f.line = lx.line();
        raw.faces.push_back(f);
      } else {
        lx.skip_line();  // points, lines, quads, …: not used
      }
    }
  }
  lx.keyword("$EndElements");
}

// Skips an unknown section up to its $End line.
void skip_section(Lexer& lx, std::string_view name) {
  const std::string end = "$End" + std::string(name.substr(1));
  for (;;) {
    const std::string_view t = lx.next(end);
    if (t == end) return;
  }
}

// Which TetMesh list a physical name maps to: 0 base, 1 tip, 2 + k chamber k, -1 none.
int tag_of(const std::string& name) {
  if (name == "base") return 0;
  if (name == "tip") return 1;
  constexpr std::string_view prefix = "chamber_";
  if (name.rfind(prefix, 0) == 0 && name.size() > prefix.size()) {
    int k = 0;
    const char* b = name.data() + prefix.size();
    const auto [p, ec] = std::from_chars(b, name.data() + name.size(), k);
    if (ec == std::errc() && p == name.data() + name.size() && k >= 1 && k <= 64) return 1 + k;
  }
  return -1;
}

// An inverted element among upright ones folds over a neighbour: two tetrahedra sharing a face
// must lie on opposite sides of it, and a face belongs to at most two tetrahedra.
void check_no_folds(const TetMesh& m, const RawMesh& raw, const std::string& file) {
  std::map<std::array<int, 3>, std::pair<int, int>> faces;  // sorted face -> (tet, opposite node)
  auto side = [&](const std::array<int, 3>& f, int p) {
    const Eigen::Vector3d a = m.nodes[f[0]], b = m.nodes[f[1]], c = m.nodes[f[2]];
    const Eigen::Vector3d u = b - a, w = c - a;
    const double v = u.cross(w).dot(m.nodes[p] - a);
    return v > 0 ? 1 : (v < 0 ? -1 : 0);
  };
  for (std::size_t t = 0; t < m.tets.size(); ++t) {
    const auto& k = m.tets[t];
    for (int o = 0; o < 4; ++o) {
      std::array<int, 3> f;
      for (int i = 0, n = 0; i < 4; ++i)
        if (i != o) f[n++] = k[i];
      std::sort(f.begin(), f.end());
      const auto [it, inserted] = faces.try_emplace(f, static_cast<int>(t), k[o]);
      if (inserted) continue;
      const int other = it->second.first;
      const std::string where = file + ":" + std::to_string(raw.tet_lines[t]) + ": ";
      if (other < 0)
        throw InputError(where + "expected a face shared by at most two tetrahedra, got a third one");
      if (side(f, it->second.second) * side(f, k[o]) >= 0)
        throw InputError(where + "expected tetrahedra that do not overlap, got one folded over the tetrahedron of line " +
                         std::to_string(raw.tet_lines[other]) + " (an inverted element)");
      it->second.first = -1;  // interior face: taken
    }
  }
}

TetMesh assemble(Lexer& lx, const RawMesh& raw) {
  const std::string& file = lx.label();
  if (!raw.have_format) throw InputError(file + ":1: expected $MeshFormat section, got none");
  if (raw.tets.empty()) throw InputError(file + ":" + std::to_string(lx.line()) + ": expected tetrahedra (element type 4), got none");
  TetMesh m;
  std::unordered_map<std::size_t, int> index;
  index.reserve(raw.node_tags.size());
  for (std::size_t i = 0; i < raw.node_tags.size(); ++i) {
    if (!index.emplace(raw.node_tags[i], static_cast<int>(i)).second) {
      throw InputError(file + ": node tag " + std::to_string(raw.node_tags[i]) + " appears twice in $Nodes");
    }
  }
  m.nodes = raw.nodes;
  auto node = [&](std::size_t tag, int line) {
    const auto it = index.find(tag);
    if (it == index.end()) {
      throw InputError(file + ":" + std::to_string(line) + ": expected a node tag listed in $Nodes, got " + std::to_string(tag));
    }
    return it->second;
  };
  for (std::size_t t = 0; t < raw.tets.size(); ++t) {
    const auto& k = raw.tets[t];
    m.tets.push_back({node(k[0], raw.tet_lines[t]), node(k[1], raw.tet_lines[t]), node(k[2], raw.tet_lines[t]),
                      node(k[3], raw.tet_lines[t])});
    if (!(std::abs(fem::tet_volume(m, static_cast<int>(t))) > 0)) {
      throw InputError(file + ":" + std::to_string(raw.tet_lines[t]) + ": expected a tetrahedron of non-zero volume, got a flat one");
    }
  }
  check_no_folds(m, raw, file);
  // Physical names of each face's entity decide its tag.
  for (const auto& f : raw.faces) {
    const auto ent = raw.entities.find({2, f.entity});
    if (ent == raw.entities.end()) continue;
    for (int phys : ent->second.physicals) {
      const auto name = raw.physical_names.find({2, std::abs(phys)});
      if (name == raw.physical_names.end()) continue;
      const int tag = tag_of(name->second);
      if (tag < 0) continue;
      const Tri tri{node(f.nodes[0], f.line), node(f.nodes[1], f.line), node(f.nodes[2], f.line)};
      if (tag == 0) m.base_faces.push_back(tri);
      else if (tag == 1) m.tip_faces.push_back(tri);
      else {
        if (m.chamber_faces.size() < static_cast<std::size_t>(tag - 1)) m.chamber_faces.resize(tag - 1);
        m.chamber_faces[tag - 2].push_back(tri);
      }
    }
  }
  try {
    fem::orient_tets_positive(m);
    fem::compact_nodes(m);
    fem::orient_tagged_faces(m);
  } catch (const std::invalid_argument& e) {
    throw InputError(file + ": " + e.what());
  }
  return m;
}

}  // namespace

void write_msh(std::ostream& out, const TetMesh& m) {
  const std::vector<TaggedSurface> surfaces = surfaces_of(m);
  const int nsurf = static_cast<int>(surfaces.size());
  out << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n";
  // Physical tags: 1 = whisker (volume), 2.. = surfaces in the order above; entity tags likewise.
  out << "$PhysicalNames\n" << nsurf + 1 << "\n3 1 \"whisker\"\n";
  for (int s = 0; s < nsurf; ++s) out << "2 " << s + 2 << " \"" << surfaces[s].name << "\"\n";
  out << "$EndPhysicalNames\n";
  out << "$Entities\n0 0 " << nsurf << " 1\n";
  for (int s = 0; s < nsurf; ++s) {
    out << s + 1 << ' ';
    write_bbox(out, m, fem::face_nodes(*surfaces[s].faces));
    out << " 1 " << s + 2 << " 0\n";
  }
  std::vector<int> all(m.nodes.size());
  for (std::size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
  out << "1 ";
  write_bbox(out, m, all);
  out << " 1 1 " << nsurf;
  for (int s = 0; s < nsurf; ++s) out << ' ' << s + 1;
  out << "\n$EndEntities\n";

  const std::size_t nn = m.nodes.size();
  out << "$Nodes\n1 " << nn << " 1 " << nn << "\n3 1 0 " << nn << "\n";
  for (std::size_t i = 0; i < nn; ++i) out << i + 1 << '\n';
  char buf[96];
  for (const auto& p : m.nodes) {
    std::snprintf(buf, sizeof buf, "%.17g %.17g %.17g\n", p.x(), p.y(), p.z());
    out << buf;
  }
  out << "$EndNodes\n";

  std::size_t nfaces = 0;
  for (const auto& s : surfaces) nfaces += s.faces->size();
  const std::size_t nel = nfaces + m.tets.size();
  out << "$Elements\n" << nsurf + 1 << ' ' << nel << " 1 " << nel << '\n';
  std::size_t tag = 1;
  for (int s = 0; s < nsurf; ++s) {
    out << "2 " << s + 1 << " 2 " << surfaces[s].faces->size() << '\n';
    for (const Tri& f : *surfaces[s].faces) out << tag++ << ' ' << f[0] + 1 << ' ' << f[1] + 1 << ' ' << f[2] + 1 << '\n';
  }
  out << "3 1 4 " << m.tets.size() << '\n';
  for (const auto& t : m.tets) {
    out << tag++ << ' ' << t[0] + 1 << ' ' << t[1] + 1 << ' ' << t[2] + 1 << ' ' << t[3] + 1 << '\n';
  }
  out << "$EndElements\n";
}

void write_msh_file(const std::string& path, const TetMesh& m) {
  write_file_atomically(path, [&](std::ostream& out) { write_msh(out, m); });
}

TetMesh read_msh(std::istream& in, const std::string& label) {
  Lexer lx(in, label);
  RawMesh raw;
  for (;;) {
    const std::string_view t = lx.peek();
    if (t.empty()) break;
    const std::string head(lx.next("a section"));
    if (head.empty() || head[0] != '$') lx.expected("a section header such as $Nodes", head);
    if (!raw.have_format && head != "$MeshFormat") lx.expected("$MeshFormat as the first section", head);
    if (head == "$MeshFormat") read_format(lx, raw);
    else if (head == "$PhysicalNames") read_physical_names(lx, raw);
    else if (head == "$Entities") read_entities(lx, raw);
    else if (head == "$Nodes") read_nodes(lx, raw);
    else if (head == "$Elements") read_elements(lx, raw);
    else skip_section(lx, head);
  }
  return assemble(lx, raw);
}

TetMesh read_msh_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open the mesh file");
  return read_msh(in, path);
}

}  // namespace codesign::io

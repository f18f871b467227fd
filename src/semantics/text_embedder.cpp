#include "semantics/text_embedder.hpp"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <fstream>
#include <iostream>
#include <sstream>

#include "io/shown.hpp"
#include "semantics/label_aliases.hpp"
#include "zeroreg/assets.hpp"
#include "zeroreg/error.hpp"

namespace zeroreg {
namespace {

std::string Lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

// IEEE 754 half -> single precision (normals, subnormals, inf/nan).
float HalfToFloat(std::uint16_t h) {
  const std::uint32_t sign = static_cast<std::uint32_t>(h & 0x8000u) << 16;
  std::uint32_t exponent = (h >> 10) & 0x1fu;
  std::uint32_t mantissa = h & 0x3ffu;
  std::uint32_t bits = 0;
  if (exponent == 0x1f) {
    bits = sign | 0x7f800000u | (mantissa << 13);
  } else if (exponent != 0) {
    bits = sign | ((exponent + 112) << 23) | (mantissa << 13);
  } else if (mantissa != 0) {  // subnormal: normalise
    exponent = 113;
    while ((mantissa & 0x400u) == 0) {
      mantissa <<= 1;
      --exponent;
    }
    bits = sign | (exponent << 23) | ((mantissa & 0x3ffu) << 13);
  } else {
    bits = sign;
  }
  float f;
  std::memcpy(&f, &bits, sizeof f);
  return f;
}

std::vector<std::string> ReadNames(const ClipTableFiles& table) {
  std::ifstream in(table.names);
  if (!in) throw MakeInputError(table.names, "cannot open the class-name list");
  std::vector<std::string> names;
  std::string line;
  const bool csv = table.names.size() > 4 && table.names.substr(table.names.size() - 4) == ".csv";
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    if (csv) {
      // Objects365_names_fix.csv: id,name,fixed_name; the embedding used the third column.
      const size_t last = line.rfind(',');
      if (last == std::string::npos) {
        throw MakeInputError(table.names, "line '" + line + "' is not id,name,fixed_name");
      }
      line = line.substr(last + 1);
    }
    names.push_back(line);
  }
  return names;
}

}  // namespace

Eigen::MatrixXf ReadNpyMatrix(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw MakeInputError(path, "cannot open the .npy file");
  char magic[8];
  if (!in.read(magic, 8) || std::memcmp(magic, "\x93NUMPY", 6) != 0) {
    throw MakeInputError(path, "not a NumPy .npy file (bad magic)");
  }
  std::uint32_t header_length = 0;
  if (magic[6] == 1) {
    unsigned char b[2];
    in.read(reinterpret_cast<char*>(b), 2);
    header_length = b[0] | (b[1] << 8);
  } else {
    unsigned char b[4];
    in.read(reinterpret_cast<char*>(b), 4);
    header_length = b[0] | (b[1] << 8) | (b[2] << 16) | (static_cast<std::uint32_t>(b[3]) << 24);
  }
  std::string header(header_length, '\0');
  if (!in.read(header.data(), header_length)) throw MakeInputError(path, "truncated .npy header");
  const bool half = header.find("'<f2'") != std::string::npos;
  const bool single = header.find("'<f4'") != std::string::npos;
  if (!half && !single) {
    throw MakeInputError(path, "dtype is not little-endian float16 or float32; header: " + header);
  }
  if (header.find("'fortran_order': False") == std::string::npos) {
    throw MakeInputError(path, "expected C order (fortran_order False)");
  }
  long rows = 0, cols = 0;
  const size_t shape = header.find("'shape': (");
  if (shape == std::string::npos ||
      std::sscanf(header.c_str() + shape, "'shape': (%ld, %ld)", &rows, &cols) != 2 || rows <= 0 ||
      cols <= 0) {
    throw MakeInputError(path, "expected a 2-D shape; header: " + header);
  }
  const size_t element = half ? 2 : 4;
  std::vector<char> data(static_cast<size_t>(rows) * cols * element);
  if (!in.read(data.data(), static_cast<std::streamsize>(data.size()))) {
    throw MakeInputError(path, "truncated: expected " + std::to_string(data.size()) +
                                   " bytes of data for shape (" + std::to_string(rows) + ", " +
                                   std::to_string(cols) + ")");
  }
  Eigen::MatrixXf m(rows, cols);
  for (long r = 0; r < rows; ++r) {
    for (long c = 0; c < cols; ++c) {
      const char* p = data.data() + (static_cast<size_t>(r) * cols + c) * element;
      if (half) {
        std::uint16_t h;
        std::memcpy(&h, p, 2);
        m(r, c) = HalfToFloat(h);
      } else {
        std::memcpy(&m(r, c), p, 4);
      }
    }
  }
  return m;
}

ClipTableEmbedder::ClipTableEmbedder(const std::vector<ClipTableFiles>& tables) {
  for (const ClipTableFiles& table : tables) {
    const Eigen::MatrixXf embeddings = ReadNpyMatrix(table.embeddings);
    const std::vector<std::string> names = ReadNames(table);
    if (static_cast<Eigen::Index>(names.size()) != embeddings.rows()) {
      throw MakeInputError(table.names, "lists " + std::to_string(names.size()) + " names but " +
                                            table.embeddings + " has " +
                                            std::to_string(embeddings.rows()) + " rows");
    }
    if (dimension_ != 0 && embeddings.cols() != dimension_) {
      throw MakeInputError(table.embeddings, "has dimension " + std::to_string(embeddings.cols()) +
                                                 ", other tables " + std::to_string(dimension_));
    }
    dimension_ = static_cast<int>(embeddings.cols());
    for (size_t i = 0; i < names.size(); ++i) {
      std::string key = Lower(names[i]);
      if (table.underscores) std::replace(key.begin(), key.end(), '_', ' ');
      // Detic stored the embeddings un-normalised (norms 8-13); cosine needs unit rows.
      const Eigen::VectorXf row = embeddings.row(static_cast<Eigen::Index>(i)).transpose();
      const float norm = row.norm();
      if (norm > 0) rows_.emplace(key, row / norm);  // first table wins
    }
  }
}

std::optional<Eigen::VectorXf> ClipTableEmbedder::Embed(const std::string& label) {
  std::string key = Lower(label);
  std::replace(key.begin(), key.end(), '_', ' ');
  auto it = rows_.find(key);
  if (it == rows_.end()) it = rows_.find(Lower(CocoSpelling(key)));  // "diningtable"
  if (it != rows_.end()) return it->second;
  if (warned_.insert(key).second) {
    std::cerr << "warning: label '" << detail::ShownText(label)
              << "' is in no CLIP table (COCO, Objects365, OpenImages, LVIS); it is compared by "
                 "label equality only\n";
  }
  return std::nullopt;
}

std::vector<ClipTableFiles> DefaultClipTables(const std::string& assets_dir) {
  const std::string dir = "clip_text_embeddings_detic/";
  auto files = [&](const char* name, const char* npy, const char* names, bool underscores) {
    return ClipTableFiles{name, RequireAsset(assets_dir, dir + npy),
                          RequireAsset(assets_dir, dir + names), underscores};
  };
  return {files("coco", "coco_clip_a+cname.npy", "coco_names.txt", false),
          files("objects365", "o365_clip_a+cnamefix.npy", "Objects365_names_fix.csv", false),
          files("openimages", "oid_clip_a+cname.npy", "oid_names.txt", false),
          files("lvis", "lvis_v1_clip_a+cname.npy", "lvis_v1_names.txt", true)};
}

std::unique_ptr<TextEmbedder> MakeTextEmbedder(const SemanticsConfig& config,
                                               const std::string& assets_dir) {
  if (config.backend == "clip-table") {
    return std::make_unique<ClipTableEmbedder>(DefaultClipTables(assets_dir));
  }
  throw MakeInputError("semantics.backend",
                       "unknown backend '" + config.backend + "'; expected \"clip-table\"");
}

}  // namespace zeroreg

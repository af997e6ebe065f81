// The scalar property types of a PLY header (both spellings: "uchar" and "uint8"), as the PLY
// reader and writer (io/ply.h) and META's PLY block (docs/FORMAT.md "Scans (format 1.1)",
// frame-file sources) name them. Part of the decoder library.
#pragma once

#include <string>
#include <vector>

#include "capz/take.h"

namespace capz {

struct PlyType {
  const char* name;   // the classic name: char uchar short ushort int uint float double
  const char* alias;  // the sized name: int8 uint8 int16 uint16 int32 uint32 float32 float64
  char type;          // 'I', 'U' or 'F' (as PCDField::type)
  int size;           // bytes
};

inline constexpr PlyType kPlyTypes[] = {
    {"char", "int8", 'I', 1},     {"uchar", "uint8", 'U', 1},    {"short", "int16", 'I', 2},
    {"ushort", "uint16", 'U', 2}, {"int", "int32", 'I', 4},      {"uint", "uint32", 'U', 4},
    {"float", "float32", 'F', 4}, {"double", "float64", 'F', 8},
};

// The type a header's name spells (either spelling), or null.
inline const PlyType* find_ply_type(const std::string& s) {
  for (const PlyType& t : kPlyTypes)
    if (s == t.name || s == t.alias) return &t;
  return nullptr;
}

// The classic name of a type and size, or null when PLY has none (8-byte integers).
inline const char* ply_type_name(char type, int size) {
  for (const PlyType& t : kPlyTypes)
    if (t.type == type && t.size == size) return t.name;
  return nullptr;
}

// The type name META's PLY block gives field f (FORMAT.md "Frame-file sources"): the one the
// source spelled for a property of f's name, type and size (`fields` and `type_names` side by
// side), else the classic name ("" when none).
inline std::string spelled_ply_type(const std::vector<PCDField>& fields,
                                    const std::vector<std::string>& type_names, const PCDField& f) {
  const char* name = ply_type_name(f.type, f.size);
  std::string spelled = name ? name : "";
  for (size_t i = 0; i < fields.size() && i < type_names.size(); ++i)
    if (fields[i].name == f.name && fields[i].type == f.type && fields[i].size == f.size)
      spelled = type_names[i];
  return spelled;
}

}  // namespace capz

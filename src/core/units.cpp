// Lengths typed by users (capz/codec.h parse_length), in the take's units.
#include <cctype>
#include <cmath>
#include <string>

#include "capz/codec.h"
#include "capz/error.h"

namespace capz {

double parse_length(const std::string& text, const std::string& take_units,
                    const std::string& assume_units) {
  std::string s;
  for (char c : text)
    if (!std::isspace(static_cast<unsigned char>(c))) s.push_back(c);
  size_t used = 0;
  double v = 0;
  try {
    v = std::stod(s, &used);
  } catch (const std::exception&) {
    fail(ErrorCode::kInvalidParameter, "", "'" + text + "' is not a length (e.g. 0.1mm)");
  }
  if (!(v >= 0) || !std::isfinite(v))
    fail(ErrorCode::kInvalidParameter, "", "'" + text + "': a length must be a finite number >= 0");
  std::string unit = s.substr(used);
  if (unit.empty()) return v;
  const double from = units_to_metres(unit);
  if (from == 0)
    fail(ErrorCode::kInvalidParameter, "", "'" + text + "': unknown unit '" + unit + "'");
  const std::string& tu = take_units.empty() ? assume_units : take_units;
  const double to = units_to_metres(tu);
  if (to == 0)
    fail(ErrorCode::kInvalidParameter, "",
         "'" + text + "' has a unit but the data's units are " +
             (tu.empty()
                  ? std::string("unknown (say them with --units mm|cm|m, or give a bare number)")
                  : "'" + tu + "', which capz does not know"));
  return v * from / to;
}

}  // namespace capz

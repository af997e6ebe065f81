#include "interop/ezc3d_snapshot.h"

#include <ezc3d/ezc3d_all.h>

#include <cstring>

namespace capz_interop {

namespace {

std::string bits_of(double v) {
  uint64_t b = 0;
  std::memcpy(&b, &v, sizeof b);
  return std::to_string(b);
}

std::string values_of(const ezc3d::ParametersNS::GroupNS::Parameter& p) {
  std::string out;
  switch (p.type()) {
    case ezc3d::DATA_TYPE::CHAR:
      for (const std::string& s : p.valuesAsString()) out += s + '\x1f';
      break;
    case ezc3d::DATA_TYPE::BYTE:
      for (int v : p.valuesAsByte()) out += std::to_string(v) + ',';
      break;
    case ezc3d::DATA_TYPE::INT:
      for (int v : p.valuesAsInt()) out += std::to_string(v) + ',';
      break;
    case ezc3d::DATA_TYPE::FLOAT:
      for (double v : p.valuesAsDouble()) out += bits_of(v) + ',';
      break;
    default:
      break;
  }
  return out;
}

void snapshot_parameters(const ezc3d::c3d& c, EzTake* t) {
  for (const auto& g : c.parameters().groups()) {
    t->groups.push_back({g.name(), g.description(), g.isLocked()});
    for (const auto& p : g.parameters()) {
      EzParam e;
      e.group = g.name();
      e.name = p.name();
      e.description = p.description();
      e.locked = p.isLocked();
      e.type = static_cast<int>(p.type());
      e.dims = p.dimension();
      e.values = values_of(p);
      t->params.push_back(std::move(e));
    }
  }
}

void snapshot_header(const ezc3d::Header& h, EzTake* t) {
  t->header = {{"points", double(h.nb3dPoints())},
               {"analog values per frame", double(h.nbAnalogs())},
               {"first frame", double(h.firstFrame())},
               {"last frame", double(h.lastFrame())},
               {"max interpolation gap", double(h.nbMaxInterpGap())},
               {"scale", double(h.scaleFactor())},
               {"analog samples per frame", double(h.nbAnalogByFrame())},
               {"frame rate", double(h.frameRate())},
               {"has rotations", double(h.hasRotationalData())},
               {"four-char event labels", double(h.fourCharPresent())},
               {"events", double(h.nbEvents())}};
  for (size_t i = 0; i < h.nbEvents(); ++i)
    t->events.push_back(bits_of(h.eventsTime(i)) + "|" + std::to_string(h.eventsDisplay(i)) + "|" +
                        h.eventsLabel(i));
}

void snapshot_points(const ezc3d::DataNS::Points3dNS::Points& pts, EzTake* t) {
  for (const auto& p : pts.points()) {
    t->xyz.insert(t->xyz.end(), {p.x(), p.y(), p.z()});
    t->residual.push_back(p.residual());
    uint8_t mask = 0;
    const std::vector<bool>& m = p.cameraMask();
    for (size_t k = 0; k < m.size() && k < 8; ++k) mask |= static_cast<uint8_t>(m[k] << k);
    t->camera.push_back(mask);
  }
}

void snapshot_rotations(const ezc3d::DataNS::RotationNS::Rotations& rot, EzTake* t) {
  for (const auto& sub : rot.subframes())
    for (const auto& r : sub.rotations()) {
      for (size_t i = 0; i < 4; ++i)
        for (size_t j = 0; j < 4; ++j) t->rotations.push_back(r(i, j));
      t->rotations.push_back(r.reliability());
    }
}

}  // namespace

EzTake read_with_ezc3d(const std::string& path) {
  const ezc3d::c3d c(path);
  EzTake t;
  snapshot_header(c.header(), &t);
  snapshot_parameters(c, &t);
  const auto& frames = c.data().frames();
  t.frames = frames.size();
  if (!frames.empty()) {
    t.points = frames[0].points().points().size();
    t.subframes = frames[0].analogs().subframes().size();
    t.channels = t.subframes ? frames[0].analogs().subframe(0).channels().size() : 0;
  }
  for (const auto& f : frames) {
    snapshot_points(f.points(), &t);
    for (const auto& sub : f.analogs().subframes())
      for (const auto& ch : sub.channels()) t.analog.push_back(ch.data());
    const size_t before = t.rotations.size();
    snapshot_rotations(f.rotations(), &t);
    t.rotations_per_frame = t.rotations.size() - before;
  }
  return t;
}

}  // namespace capz_interop

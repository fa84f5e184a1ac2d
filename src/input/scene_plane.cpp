// What a plane scene (2D) checks of its bodies once the domain is known, its default domain, and
// the hole measure's options.
#include "scene_options.hpp"

#include <algorithm>
#include <cmath>

namespace gimp::input {

namespace {

/// The values of the option that gave the body's shape, as the user wrote them.
std::string shapeText(const Body<2> &b) {
  const Shape &s = b.shape;
  if (b.shapeOption == "circle") {
    const double v[3] = {s.cx, s.cy, s.a};
    return fmtList(v, 3);
  }
  if (b.shapeOption == "ellipse") {
    const double v[4] = {s.cx, s.cy, s.a, s.b};
    return fmtList(v, 4);
  }
  if (b.shapeOption == "polygon") return fmtList(s.xy.data(), s.xy.size());
  if (b.shapeOption == "file") return b.file;
  return fmtList(b.box.data(), 4);
}

} // namespace

void checkBodies(const Scene<2> &sc) {
  for (size_t k = 0; k < sc.bodies.size(); ++k)
    for (size_t q = 0; q < k; ++q) {
      const BoxOf<2> &a = sc.bodies[q].box, &b = sc.bodies[k].box;
      if (bodiesOverlap(sc.bodies[q], sc.bodies[k]))
        Options::bad("gimp_body" + std::to_string(k) + "_" + sc.bodies[k].shapeOption,
                     shapeText(sc.bodies[k]),
                     "overlaps body " + std::to_string(q) + " (bounding box " +
                         fmtList(a.data(), 4) + ", body " + std::to_string(k) + "'s " +
                         fmtList(b.data(), 4) + "): bodies may touch but not overlap");
    }
  for (size_t k = 0; k < sc.bodies.size(); ++k)
    checkFileParticles<2>(sc, k);
  for (size_t k = 0; k < sc.bodies.size(); ++k) {
    const BoxOf<2> &b = sc.bodies[k].box;
    if (b[0] < sc.domain[0] || b[1] < sc.domain[1] || b[2] > sc.domain[2] || b[3] > sc.domain[3])
      Options::bad("gimp_body" + std::to_string(k) + "_" + sc.bodies[k].shapeOption,
                   shapeText(sc.bodies[k]),
                   "lies outside the grid domain " + fmtList(sc.domain.data(), 4) +
                       " (bounding box " + fmtList(b.data(), 4) + ")");
  }
}

void domainAroundBodies(Scene<2> &sc) {
  // The bodies' bounding box padded by pad cells, whole cells from its lower corner.
  BoxOf<2> &dom = sc.domain;
  dom[0] = dom[1] = 1e300;
  dom[2] = dom[3] = -1e300;
  for (const Body<2> &b : sc.bodies) {
    dom[0] = std::min(dom[0], b.box[0]);
    dom[1] = std::min(dom[1], b.box[1]);
    dom[2] = std::max(dom[2], b.box[2]);
    dom[3] = std::max(dom[3], b.box[3]);
  }
  dom[0] -= sc.pad * sc.h;
  dom[1] -= sc.pad * sc.h;
  dom[2] += sc.pad * sc.h;
  dom[3] += sc.pad * sc.h;
  dom[2] = dom[0] + std::ceil((dom[2] - dom[0]) / sc.h - 1e-9) * sc.h;
  dom[3] = dom[1] + std::ceil((dom[3] - dom[1]) / sc.h - 1e-9) * sc.h;
}

void readHoleMeasure(const Options &o, Measures &sc) {
  const std::vector<double> hm = o.reals("gimp_hole_measure");
  bool loadGiven = false;
  sc.holeLoad = o.real("gimp_hole_measure_load", 0.0, &loadGiven);
  sc.holeMeasure = !hm.empty();
  if (o.help()) return;
  if (sc.holeMeasure && !(hm[2] > 0))
    Options::bad("gimp_hole_measure", fmtList(hm.data(), 3), "needs cx,cy,r with r > 0 [m]");
  if (sc.holeMeasure) std::copy(hm.begin(), hm.end(), sc.hole);
  if (loadGiven && !sc.holeMeasure)
    Options::bad("gimp_hole_measure_load", formatNumber(sc.holeLoad),
                 "has no effect without -gimp_hole_measure cx,cy,r");
  if (sc.holeMeasure && sc.holeLoad == 0)
    Options::bad("gimp_hole_measure_load", "0",
                 "the hole measure needs the remote stress p != 0 [Pa]");
}

} // namespace gimp::input

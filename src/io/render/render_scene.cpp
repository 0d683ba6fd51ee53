#include "io/render/render_scene.hpp"

#include <GL/gl.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include <Eigen/Geometry>

namespace codesign::io {

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

Eigen::Vector3d back_direction(const Camera& c) {
  const double az = c.azimuth_deg * kDeg, el = c.elevation_deg * kDeg;
  return {std::sin(az) * std::cos(el), -std::cos(az) * std::cos(el), std::sin(el)};
}

// Camera basis: right, up, back (towards the eye).
void basis(const Camera& c, Eigen::Vector3d& right, Eigen::Vector3d& up, Eigen::Vector3d& back) {
  back = back_direction(c);
  const Eigen::Vector3d forward = -back;
  right = forward.cross(Eigen::Vector3d::UnitZ());
  if (right.norm() < 1e-9) right = Eigen::Vector3d::UnitX();  // looking straight down or up
  right.normalize();
  up = right.cross(forward);
}

void vertex(const Eigen::Vector3d& p) { glVertex3d(p.x(), p.y(), p.z()); }
void normal(const Eigen::Vector3d& n) { glNormal3d(n.x(), n.y(), n.z()); }
void colour(float r, float g, float b) { glColor3f(r, g, b); }

// A box with corners c + Σ ±h_i a_i (a_i orthonormal axes), flat-shaded.
void draw_box(const Eigen::Vector3d& c, const Eigen::Matrix3d& axes, const Eigen::Vector3d& h) {
  glBegin(GL_QUADS);
  for (int ax = 0; ax < 3; ++ax)
    for (int sign = -1; sign <= 1; sign += 2) {
      const Eigen::Vector3d n = sign * axes.col(ax);
      const Eigen::Vector3d u = axes.col((ax + 1) % 3) * h[(ax + 1) % 3];
      const Eigen::Vector3d v = axes.col((ax + 2) % 3) * h[(ax + 2) % 3];
      const Eigen::Vector3d f = c + n * h[ax];
      normal(n);
      // counter-clockwise seen from outside
      if (sign > 0) {
        vertex(f - u - v), vertex(f + u - v), vertex(f + u + v), vertex(f - u + v);
      } else {
        vertex(f - u - v), vertex(f - u + v), vertex(f + u + v), vertex(f + u - v);
      }
    }
  glEnd();
}

// A closed cylinder (or cone when r1 = 0) from a to b, radii r0 at a and r1 at b.
void draw_cylinder(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double r0, double r1, int segments) {
  const Eigen::Vector3d axis = (b - a).normalized();
  Eigen::Vector3d u = axis.unitOrthogonal();
  const Eigen::Vector3d v = axis.cross(u);
  const double slope = (r0 - r1) / (b - a).norm();
  glBegin(GL_QUAD_STRIP);
  for (int k = 0; k <= segments; ++k) {
    const double phi = 2.0 * std::numbers::pi * k / segments;
    const Eigen::Vector3d radial = std::cos(phi) * u + std::sin(phi) * v;
    normal((radial + slope * axis).normalized());
    vertex(a + r0 * radial);
    vertex(b + r1 * radial);
  }
  glEnd();
  for (int end = 0; end < 2; ++end) {
    const double r = end ? r1 : r0;
    if (r <= 0.0) continue;
    const Eigen::Vector3d c = end ? b : a;
    const Eigen::Vector3d n = end ? axis : Eigen::Vector3d(-axis);
    glBegin(GL_TRIANGLE_FAN);
    normal(n);
    vertex(c);
    for (int k = 0; k <= segments; ++k) {
      const double phi = 2.0 * std::numbers::pi * (end ? k : segments - k) / segments;
      vertex(c + r * (std::cos(phi) * u + std::sin(phi) * v));
    }
    glEnd();
  }
}

void draw_whisker(const SceneFrame& f, const ColourScale& scale, bool vertex_arrays) {
  const std::size_t n = f.vertices.size();
  // Smooth normals: area-weighted sum of the adjacent faces' normals.
  std::vector<Eigen::Vector3f> normals(n, Eigen::Vector3f::Zero());
  for (const auto& t : f.triangles) {
    const Eigen::Vector3f& a = f.vertices[static_cast<std::size_t>(t[0])];
    const Eigen::Vector3f fn = (f.vertices[static_cast<std::size_t>(t[1])] - a).cross(f.vertices[static_cast<std::size_t>(t[2])] - a);
    for (int k = 0; k < 3; ++k) normals[static_cast<std::size_t>(t[k])] += fn;
  }
  for (auto& v : normals) {
    const float len = v.norm();
    if (len > 0.f) v /= len;
  }
  std::vector<ColourF> colours(n);
  for (std::size_t i = 0; i < n; ++i) colours[i] = strain_colour(scale.fraction(f.strain[i]));
  if (vertex_arrays) {
    glEnableClientState(GL_VERTEX_ARRAY);
    glEnableClientState(GL_NORMAL_ARRAY);
    glEnableClientState(GL_COLOR_ARRAY);
    glVertexPointer(3, GL_FLOAT, sizeof(Eigen::Vector3f), f.vertices.data());
    glNormalPointer(GL_FLOAT, sizeof(Eigen::Vector3f), normals.data());
    glColorPointer(3, GL_FLOAT, sizeof(ColourF), colours.data());
    glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(3 * f.triangles.size()), GL_UNSIGNED_INT, f.triangles.data());
    glDisableClientState(GL_VERTEX_ARRAY);
    glDisableClientState(GL_NORMAL_ARRAY);
    glDisableClientState(GL_COLOR_ARRAY);
  } else {
    glBegin(GL_TRIANGLES);
    for (const auto& t : f.triangles)
      for (int k = 0; k < 3; ++k) {
        const auto i = static_cast<std::size_t>(t[k]);
        glColor3f(colours[i].r, colours[i].g, colours[i].b);
        glNormal3f(normals[i].x(), normals[i].y(), normals[i].z());
        glVertex3f(f.vertices[i].x(), f.vertices[i].y(), f.vertices[i].z());
      }
    glEnd();
  }
}

void draw_plate(const SceneFrame& f) {
  constexpr double thickness = 2.0;
  colour(0.62f, 0.64f, 0.68f);
  const Eigen::Vector3d c(0.5 * (f.plate_x0_mm + f.plate_x1_mm), 0.0, f.plate_z_mm - 0.5 * thickness);
  const Eigen::Vector3d h(0.5 * (f.plate_x1_mm - f.plate_x0_mm), f.plate_half_width_mm, 0.5 * thickness);
  draw_box(c, Eigen::Matrix3d::Identity(), h);
}

void draw_base(const SceneFrame& f) {
  const double r = f.base_radius_mm;
  const double c = std::cos(f.base_angle_rad), s = std::sin(f.base_angle_rad);
  Eigen::Matrix3d rot;  // R_y: the whisker frame's axes in the world
  rot << c, 0.0, s, 0.0, 1.0, 0.0, -s, 0.0, c;
  // Clamp block behind the clamped face (whisker-frame x in [-8, 0]).
  colour(0.25f, 0.27f, 0.30f);
  draw_box(rot * Eigen::Vector3d(-4.0, 0.0, 0.0), rot, Eigen::Vector3d(4.0, r + 4.0, r + 4.0));
  // Motor drum on the rotation axis (world y), behind the whisker.
  const double y0 = r + 4.0, y1 = r + 16.0, drum = r + 10.0;
  colour(0.45f, 0.47f, 0.52f);
  draw_cylinder(Eigen::Vector3d(0.0, y0, 0.0), Eigen::Vector3d(0.0, y1, 0.0), drum, drum, 48);
  // Index mark on the drum's front face, pointing away from the whisker: turns with α + θ.
  colour(0.95f, 0.55f, 0.10f);
  const Eigen::Vector3d dir = -(rot * Eigen::Vector3d::UnitX());
  Eigen::Matrix3d axes;
  axes.col(0) = dir;
  axes.col(1) = Eigen::Vector3d::UnitY();
  axes.col(2) = dir.cross(Eigen::Vector3d::UnitY());
  draw_box(Eigen::Vector3d(0.0, y0 - 0.6, 0.0) + dir * (0.5 * drum), axes, Eigen::Vector3d(0.5 * drum, 0.5, 1.5));
}

void draw_force_arrow(const SceneFrame& f, double mm_per_mN) {
  const double len = f.force_mN * mm_per_mN;
  if (!(len > 0.0)) return;
  const double head = std::min(6.0, 0.4 * len);
  const Eigen::Vector3d a = f.force_point_mm;
  const Eigen::Vector3d b = a + Eigen::Vector3d(0.0, 0.0, len - head);
  const Eigen::Vector3d tip = a + Eigen::Vector3d(0.0, 0.0, len);
  colour(0.85f, 0.10f, 0.65f);
  if (len - head > 0.0) draw_cylinder(a, b, 0.8, 0.8, 16);
  draw_cylinder(b, tip, 2.2, 0.0, 24);
}

}  // namespace

Eigen::Vector3d Camera::eye() const { return target + distance_mm * back_direction(*this); }

Eigen::Matrix4d Camera::view() const {
  Eigen::Vector3d right, up, back;
  basis(*this, right, up, back);
  const Eigen::Vector3d e = eye();
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.block<1, 3>(0, 0) = right.transpose();
  m.block<1, 3>(1, 0) = up.transpose();
  m.block<1, 3>(2, 0) = back.transpose();
  m(0, 3) = -right.dot(e);
  m(1, 3) = -up.dot(e);
  m(2, 3) = -back.dot(e);
  return m;
}

Eigen::Matrix4d Camera::projection(double aspect) const {
  const double f = 1.0 / std::tan(0.5 * fov_deg * kDeg);
  const double near = 0.05 * distance_mm, far = 4.0 * distance_mm;
  Eigen::Matrix4d p = Eigen::Matrix4d::Zero();
  p(0, 0) = f / aspect;
  p(1, 1) = f;
  p(2, 2) = (far + near) / (near - far);
  p(2, 3) = 2.0 * far * near / (near - far);
  p(3, 2) = -1.0;
  return p;
}

Eigen::Vector2d project_to_pixel(const Camera& camera, const Viewport& vp, const Eigen::Vector3d& p) {
  const double aspect = static_cast<double>(vp.width) / vp.height;
  const Eigen::Vector4d clip = camera.projection(aspect) * camera.view() * Eigen::Vector4d(p.x(), p.y(), p.z(), 1.0);
  const double x = clip.x() / clip.w(), y = clip.y() / clip.w();
  return {vp.x0 + 0.5 * (x + 1.0) * vp.width, vp.y0 + 0.5 * (1.0 - y) * vp.height};
}

Camera fit_camera(const SceneFrame& frame, double azimuth_deg, double elevation_deg, double fov_deg, double aspect,
                  double margin) {
  // Box around whisker, plate and base.
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = Eigen::Vector3d::Constant(-1e300);
  auto add = [&](const Eigen::Vector3d& p) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  };
  for (const auto& v : frame.vertices) add(v.cast<double>());
  const double r = frame.base_radius_mm + 10.0;
  add({-r, -r, -r});
  add({r, frame.base_radius_mm + 16.0, r});
  add({frame.plate_x0_mm, -frame.plate_half_width_mm, frame.plate_z_mm - 2.0});
  add({frame.plate_x1_mm, frame.plate_half_width_mm, frame.plate_z_mm});
  Camera cam;
  cam.azimuth_deg = azimuth_deg;
  cam.elevation_deg = elevation_deg;
  cam.fov_deg = fov_deg;
  cam.target = 0.5 * (lo + hi);
  Eigen::Vector3d right, up, back;
  basis(cam, right, up, back);
  const double tv = std::tan(0.5 * fov_deg * kDeg), th = tv * aspect;
  // The eye at distance d sees corner p (relative to the target) inside the frustum when
  // d ≥ |p·right|/tan(h/2) + p·back and d ≥ |p·up|/tan(v/2) + p·back.
  double d = 1.0;
  for (int k = 0; k < 8; ++k) {
    const Eigen::Vector3d c((k & 1) ? hi.x() : lo.x(), (k & 2) ? hi.y() : lo.y(), (k & 4) ? hi.z() : lo.z());
    const Eigen::Vector3d p = (c - cam.target) * margin;
    d = std::max({d, std::abs(p.dot(right)) / th + p.dot(back), std::abs(p.dot(up)) / tv + p.dot(back)});
  }
  cam.distance_mm = d;
  return cam;
}

void check_frame(const SceneFrame& f) {
  if (f.strain.size() != f.vertices.size())
    throw std::invalid_argument("render: " + std::to_string(f.strain.size()) + " strain values for " +
                                std::to_string(f.vertices.size()) + " vertices");
  const auto n = static_cast<int>(f.vertices.size());
  for (const auto& t : f.triangles)
    for (int i : t)
      if (i < 0 || i >= n) throw std::invalid_argument("render: triangle vertex index out of range");
}

void draw_scene_gl(const SceneFrame& frame, const Camera& camera, const ColourScale& strain, const SceneStyle& style,
                   const Viewport& vp, int image_height) {
  check_frame(frame);
  const GLint gl_y = image_height - vp.y0 - vp.height;
  glViewport(vp.x0, gl_y, vp.width, vp.height);
  glEnable(GL_SCISSOR_TEST);
  glScissor(vp.x0, gl_y, vp.width, vp.height);
  glClear(GL_DEPTH_BUFFER_BIT);
  glDisable(GL_SCISSOR_TEST);

  glMatrixMode(GL_PROJECTION);
  glLoadMatrixd(camera.projection(static_cast<double>(vp.width) / vp.height).data());
  glMatrixMode(GL_MODELVIEW);
  glLoadIdentity();
  // Light fixed to the viewer: from the upper left, in front.
  const GLfloat light_dir[] = {-0.35f, 0.55f, 0.76f, 0.0f};
  glLightfv(GL_LIGHT0, GL_POSITION, light_dir);
  glLoadMatrixd(camera.view().data());

  glEnable(GL_DEPTH_TEST);
  glEnable(GL_LIGHTING);
  glEnable(GL_LIGHT0);
  glEnable(GL_NORMALIZE);
  glEnable(GL_COLOR_MATERIAL);
  glColorMaterial(GL_FRONT_AND_BACK, GL_AMBIENT_AND_DIFFUSE);
  glShadeModel(GL_SMOOTH);
  const GLfloat none[] = {0.f, 0.f, 0.f, 1.f};
  const GLfloat ambient[] = {0.32f, 0.32f, 0.32f, 1.f};
  const GLfloat diffuse[] = {0.68f, 0.68f, 0.68f, 1.f};
  glLightModelfv(GL_LIGHT_MODEL_AMBIENT, none);
  glLightfv(GL_LIGHT0, GL_AMBIENT, ambient);
  glLightfv(GL_LIGHT0, GL_DIFFUSE, diffuse);
  glLightfv(GL_LIGHT0, GL_SPECULAR, none);
  glMaterialfv(GL_FRONT_AND_BACK, GL_SPECULAR, none);

  draw_whisker(frame, strain, style.vertex_arrays);
  if (style.plate) draw_plate(frame);
  if (style.base) draw_base(frame);
  if (style.force_arrow) draw_force_arrow(frame, style.arrow_mm_per_mN);
}

}  // namespace codesign::io

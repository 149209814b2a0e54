#include "core/mass.hpp"

namespace grip {

MassProperties sphereMass(double radius, double density) {
  MassProperties mp;
  mp.volume = 4.0 / 3.0 * kPi * radius * radius * radius;
  mp.mass = density * mp.volume;
  mp.inertia = Mat3::Identity() * (0.4 * mp.mass * radius * radius);
  return mp;
}

MassProperties boxMass(const Vec3& h, double density) {
  MassProperties mp;
  mp.volume = 8.0 * h.x() * h.y() * h.z();
  mp.mass = density * mp.volume;
  const Vec3 s = 4.0 * h.cwiseProduct(h);  // full edge lengths squared
  mp.inertia.diagonal() = Vec3(s.y() + s.z(), s.x() + s.z(), s.x() + s.y()) * (mp.mass / 12.0);
  return mp;
}

MassProperties capsuleMass(double r, double hh, double density) {
  MassProperties mp;
  const double cylVolume = kPi * r * r * 2.0 * hh;
  const double sphVolume = 4.0 / 3.0 * kPi * r * r * r;
  const double mc = density * cylVolume, ms = density * sphVolume;
  mp.volume = cylVolume + sphVolume;
  mp.mass = mc + ms;
  const double axial = mc * r * r / 2.0 + ms * 0.4 * r * r;
  const double H = 2.0 * hh;
  const double lateral =
      mc * (H * H / 12.0 + r * r / 4.0) + ms * (0.4 * r * r + H * H / 4.0 + 3.0 * H * r / 8.0);
  mp.inertia.diagonal() = Vec3(lateral, axial, lateral);
  return mp;
}

MassProperties meshMass(const std::vector<Vec3>& v, const std::vector<std::array<int, 3>>& tris,
                        double density) {
  // Sum signed tetrahedra (origin, a, b, c): volume, first and second moments.
  double vol = 0.0;
  Vec3 first = Vec3::Zero();
  Mat3 second = Mat3::Zero();  // integral of x x^T over the volume
  // Shift to a reference point inside the mesh's bounds to limit cancellation.
  Vec3 ref = Vec3::Zero();
  for (const Vec3& p : v) ref += p;
  if (!v.empty()) ref /= static_cast<double>(v.size());
  const Mat3 canonical = (Mat3() << 2, 1, 1, 1, 2, 1, 1, 1, 2).finished() / 120.0;
  for (const auto& t : tris) {
    const Vec3 a = v[t[0]] - ref, b = v[t[1]] - ref, c = v[t[2]] - ref;
    Mat3 A;
    A.col(0) = a, A.col(1) = b, A.col(2) = c;
    const double det = A.determinant();
    vol += det / 6.0;
    first += det / 24.0 * (a + b + c);
    second += det * A * canonical * A.transpose();
  }
  MassProperties mp;
  mp.volume = vol;
  mp.mass = density * vol;
  if (vol <= 0.0) return mp;
  const Vec3 c = first / vol;
  mp.com = c + ref;
  const Mat3 cov = density * second - mp.mass * c * c.transpose();  // about com
  mp.inertia = Mat3::Identity() * cov.trace() - cov;
  return mp;
}

Mat3 shiftInertia(const Mat3& I, double m, const Vec3& d) {
  return I + m * (d.squaredNorm() * Mat3::Identity() - d * d.transpose());
}

Mat3 rotateInertia(const Mat3& I, const Quat& q) {
  const Mat3 R = q.toRotationMatrix();
  return R * I * R.transpose();
}

}  // namespace grip

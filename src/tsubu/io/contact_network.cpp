#include "tsubu/io/contact_network.hpp"

#include <algorithm>
#include <iomanip>
#include <tuple>

#include "tsubu/io/checked_file.hpp"

namespace tsubu {

std::vector<NetworkContact> contact_network(const World& world, const std::vector<ContactRecord>& contacts) {
  const Particles& p = world.particles;
  std::vector<NetworkContact> out;
  out.reserve(contacts.size());
  for (const ContactRecord& c : contacts) {
    NetworkContact n;
    // A pair seen from its particle with the smaller id: the record's i (the contact list's
    // orientation, world/contact_list.hpp), so the record's forces and history are the pair's.
    n.id_i = p.id[c.i];
    n.centre_i = p.position[c.i];
    if (c.wall) {
      n.wall = static_cast<int>(world.wall_of(c.j));
      n.element = c.j;
      WallTouch touch;
      world.touch_element(c.j, n.centre_i, touch);
      n.branch = -touch.distance * touch.normal;  // to the nearest point of the surface
    } else {
      n.id_j = p.id[c.j];
      n.branch = -world.domain.separation(n.centre_i, p.position[c.j]);
    }
    // Pairs: the lever arm of the torques, r_i - overlap/2 along the line of centres.
    const double arm = c.wall ? norm(n.branch) : p.radius[c.i] - 0.5 * c.overlap;
    n.point = n.centre_i + (arm / norm(n.branch)) * n.branch;
    n.normal_force = c.normal_force;
    n.tangential_force = c.tangential_force;
    n.overlap = c.overlap;
    n.history = c.history;  // as the law saw it, from i
    out.push_back(n);
  }
  // Pairs by (id_i, id_j), then walls by (id, wall, triangle): the same file whatever the numbering.
  std::sort(out.begin(), out.end(), [](const NetworkContact& a, const NetworkContact& b) {
    return std::tuple(a.wall >= 0, a.id_i, a.id_j, a.element) < std::tuple(b.wall >= 0, b.id_i, b.id_j, b.element);
  });
  return out;
}

void write_contacts_csv(const std::string& path, const std::vector<NetworkContact>& contacts, double time, bool rolling) {
  CheckedFile f(path);
  f << "time[s],i,j,wall,px[m],py[m],pz[m],bx[m],by[m],bz[m],fnx[N],fny[N],fnz[N],ftx[N],fty[N],ftz[N],overlap[m],"
       "xi_x[m],xi_y[m],xi_z[m],normal_history0,normal_history1"
    << (rolling ? ",mr_x[N m],mr_y[N m],mr_z[N m]\n" : "\n") << std::setprecision(17);
  for (const NetworkContact& c : contacts) {
    f << time << ',' << c.id_i << ',' << c.id_j << ',' << c.wall;
    for (const Vec3* v : {&c.point, &c.branch, &c.normal_force, &c.tangential_force}) f << ',' << v->x << ',' << v->y << ',' << v->z;
    f << ',' << c.overlap << ',' << c.history.xi.x << ',' << c.history.xi.y << ',' << c.history.xi.z << ','
      << c.history.normal[0] << ',' << c.history.normal[1];
    if (rolling) f << ',' << c.history.rolling.x << ',' << c.history.rolling.y << ',' << c.history.rolling.z;
    f << '\n';
  }
  f.close();
}

}  // namespace tsubu

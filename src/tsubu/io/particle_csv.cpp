#include "tsubu/io/particle_csv.hpp"

#include <iomanip>
#include <vector>

#include "tsubu/io/checked_file.hpp"

namespace tsubu {

void write_particles_csv(const std::string& path, const Particles& p) {
  const std::vector<std::size_t> order = p.in_id_order();
  CheckedFile f(path);
  f << "id,material,radius[m],x[m],y[m],z[m],vx[m/s],vy[m/s],vz[m/s],wx[rad/s],wy[rad/s],wz[rad/s]\n"
    << std::setprecision(17);  // reads back as the same doubles
  for (std::size_t i : order) {
    f << p.id[i] << ',' << p.material[i] << ',' << p.radius[i];
    for (const Vec3* v : {&p.position[i], &p.velocity[i], &p.omega[i]}) f << ',' << v->x << ',' << v->y << ',' << v->z;
    f << '\n';
  }
  f.close();
}

}  // namespace tsubu

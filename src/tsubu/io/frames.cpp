#include "tsubu/io/frames.hpp"

#include <algorithm>
#include <cstdio>
#include <stdexcept>

#include "tsubu/io/contact_network.hpp"

namespace tsubu {

namespace fs = std::filesystem;

FrameSeries::FrameSeries(const fs::path& out_dir, bool contacts, bool walls)
    : dir_(out_dir / kFramesDir),
      contacts_(contacts),
      walls_(walls),
      particles_((dir_ / "particles.pvd").string()),
      contact_index_((dir_ / "contacts.pvd").string()),
      wall_index_((dir_ / "walls.pvd").string()) {
  fs::create_directories(dir_);
}

std::string FrameSeries::name(const char* stem, std::size_t k, const char* ext) {
  char text[48];
  std::snprintf(text, sizeof text, "%s_%05zu.%s", stem, k, ext);
  return text;
}

void FrameSeries::restore(const std::vector<std::pair<double, std::string>>& frames) {
  std::vector<std::pair<double, std::string>> contacts, walls;
  for (std::size_t k = 0; k < frames.size(); ++k) {
    std::vector<std::string> files = {frames[k].second};
    if (contacts_) {
      contacts.emplace_back(frames[k].first, name("contacts", k, "vtp"));
      files.push_back(contacts.back().second);
      files.push_back(name("contacts", k, "csv"));
    }
    if (walls_) walls.emplace_back(frames[k].first, name("walls", k, "vtp")), files.push_back(walls.back().second);
    for (const std::string& file : files)
      if (!fs::exists(dir_ / file))
        throw std::runtime_error((dir_ / file).string() +
                                 " is missing: the frames up to the checkpoint are part of the outputs a resume continues");
  }
  particles_.restore(frames);
  contact_index_.restore(std::move(contacts));
  wall_index_.restore(std::move(walls));
}

void FrameSeries::write(const World& world, const ForceField& forces) {
  const std::size_t k = frames().size();
  auto add = [&](PvdIndex& index, const std::string& file) {
    index.add(world.time, file);
    unsynced_.push_back(dir_ / file);
    if (std::find(unsynced_.begin(), unsynced_.end(), index.path()) == unsynced_.end()) unsynced_.push_back(index.path());
  };
  const std::string particles = name("frame", k, "vtu");
  write_vtu((dir_ / particles).string(), world.particles, world.time);
  add(particles_, particles);
  if (contacts_) {
    const std::vector<NetworkContact> network = contact_network(world, forces.touching_contacts(world));
    const std::string vtp = name("contacts", k, "vtp"), csv = name("contacts", k, "csv");
    write_contacts_vtp((dir_ / vtp).string(), network, world.time, forces.resists_rolling());
    write_contacts_csv((dir_ / csv).string(), network, world.time, forces.resists_rolling());
    unsynced_.push_back(dir_ / csv);
    add(contact_index_, vtp);
  }
  if (walls_) {
    const std::string vtp = name("walls", k, "vtp");
    write_walls_vtp((dir_ / vtp).string(), world.walls, world.domain, world.time);
    add(wall_index_, vtp);
  }
}

}  // namespace tsubu

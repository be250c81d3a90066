// The example law of docs/contact-laws.md ("How to add a contact law"), compiled as the
// document has it (tests/doc_snippet.cmake writes example_law.hpp from it) and registered
// here beside the registered laws: the generic loader, builder and force evaluation take
// it with nothing else added.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <variant>

#include "example_law.hpp"
#include "tsubu/contact/law.hpp"
#include "tsubu/core/error.hpp"
#include "tsubu/scenario/law_keys.hpp"

namespace tsubu {
namespace {

// Registering a law is adding it to the variant.
template <class Variant, class Law>
struct WithLaw;
template <class... Laws, class Law>
struct WithLaw<std::variant<Laws...>, Law> {
  using type = std::variant<Laws..., Law>;
};
using Normals = WithLaw<NormalModel, HookeDashpot>::type;
static_assert(well_formed_normal_law<HookeDashpot>());
constexpr auto kNormals = traits_of_all<Normals>();

const Material kGlass{"glass", 2500, 7e10, 0.2};

// [contact.default] of a scenario, read by the generic loader with the example registered.
ContactSpec read(const std::string& entry, std::string_view integrator = "velocity_verlet") {
  const std::string text = "[contact.default]\n" + entry;
  const toml::table root = toml::parse(std::string_view(text), std::string_view("example.toml"));
  Section s(*root["contact"]["default"].as_table(), "contact.default", "example.toml");
  ContactSpec spec = read_contact_spec(s, integrator, kNormals, kTangentialLaws);
  s.finish();
  return spec;
}

// The message a table is refused with.
std::string refusal(const std::string& entry, std::string_view integrator = "velocity_verlet") {
  try {
    read(entry, integrator);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(accepted)";
}

HookeDashpot build(const ContactSpec& spec) {
  const Normals law = build_law<Normals>(spec.normal, MaterialPair{kGlass, kGlass, spec.restitution, spec.friction}, spec.values);
  return std::get<HookeDashpot>(law);
}

TEST(ExampleLaw, KeysAreReadWithTheirDefaults) {
  const ContactSpec spec = read("normal = \"hooke_dashpot\"\nstiffness = 1e4\n");
  EXPECT_EQ(spec.normal, "hooke_dashpot");
  EXPECT_EQ(spec.tangential, "mindlin");  // the default partner
  EXPECT_EQ(spec.values.number("stiffness"), 1e4);
  EXPECT_EQ(spec.values.find("damping"), nullptr);
  const HookeDashpot law = build(spec);
  EXPECT_EQ(law.k_n, 1e4);
  EXPECT_EQ(law.eta, 0.0);  // the default
  EXPECT_EQ(build(read("normal = \"hooke_dashpot\"\nstiffness = 1e4\ndamping = 0.05\n")).eta, 0.05);
  // It has rates: block steps may run it.
  EXPECT_EQ(read("normal = \"hooke_dashpot\"\nstiffness = 1e4\n", "block_hermite").normal, "hooke_dashpot");
}

TEST(ExampleLaw, BadValuesGetTheStandardMessages) {
  auto has = [](const std::string& message, const std::string& phrase) {
    return message.find(phrase) != std::string::npos;
  };
  std::string m = refusal("normal = \"hooke_dashpot\"\nstiffness = 1e4\ndamping = -1\n");
  EXPECT_TRUE(has(m, "example.toml:4: contact.default.damping: is the dashpot eta_n in N s/m and must be >= 0, got -1")) << m;
  m = refusal("normal = \"hooke_dashpot\"\ndamping = 0.05\n");
  EXPECT_TRUE(has(m, "contact.default.stiffness: is required with normal = \"hooke_dashpot\": the spring constant k_n in N/m, a number > 0")) << m;
  m = refusal("normal = \"hooke_dashpot\"\nstiffness = \"1e4\"\n");
  EXPECT_TRUE(has(m, "contact.default.stiffness: must be a number, got the string \"1e4\"")) << m;
  // Its keys are refused with another law, by name.
  m = refusal("normal = \"hertz_tsuji\"\ndamping = 0.05\n");
  EXPECT_TRUE(has(m, "contact.default.damping: is used only with normal = \"hooke_dashpot\"")) << m;
  m = refusal("normal = \"hertz_tsuji\"\nstiffness = 1e4\n");
  EXPECT_TRUE(has(m, "is used only with normal = \"linear\", \"energy_conserving\", \"energy_conserving_2005\" or \"hooke_dashpot\"")) << m;
  // Its name is among the words `normal` allows, and among the laws block steps run.
  m = refusal("normal = \"hooke\"\n");
  EXPECT_TRUE(has(m, "\"energy_conserving_2005\", \"hooke_dashpot\"")) << m;
  m = refusal("normal = \"energy_conserving\"\nstiffness = 1e4\n", "block_hermite");
  EXPECT_TRUE(has(m, "allowed with it: \"linear\", \"hertz_tsuji\", \"hertz_sediment\", \"hooke_dashpot\"")) << m;
  // Values set by code are checked by the builder.
  ContactSpec spec = read("normal = \"hooke_dashpot\"\nstiffness = 1e4\n");
  spec.values.set("damping", -1.0);
  EXPECT_THROW(build(spec), std::invalid_argument);
}

TEST(ExampleLaw, BuildsFromTwoMaterialsWithItsTangentialPartner) {
  const ContactSpec spec = read("normal = \"hooke_dashpot\"\nstiffness = 1e4\ntangential = \"linear_coulomb\"\nfriction = 0.3\n");
  const MaterialPair pair{kGlass, kGlass, spec.restitution, spec.friction};
  const HookeDashpot normal = build(spec);
  const auto tangential = build_law<TangentialModel>(spec.tangential, pair, spec.values, normal_side(normal, pair.poisson()));
  const auto& t = std::get<LinearCoulomb>(tangential);
  EXPECT_DOUBLE_EQ(t.stiffness_ratio, 2 * 0.8 / 1.8);             // 2(1 - sigma)/(2 - sigma)
  EXPECT_DOUBLE_EQ(t.damping_ratio, std::sqrt(2 * 0.8 / 1.8));  // a linear spring: sqrt(kappa)
  EXPECT_EQ(t.mu, 0.3);
}

// Two equal grains head on at approach speed u, through the generic evaluate(): the
// restitution, the peak force and how long the contact lasts.
struct Collision {
  double restitution = 0, peak_force = 0, duration = 0;
};
Collision head_on(const HookeDashpot& law, double m_eff, double r_eff, double u, double dt) {
  ContactGeometry g;
  g.n = {1, 0, 0};
  g.m_eff = m_eff, g.r_eff = r_eff, g.d_mean = g.d_small = 4 * r_eff, g.dt = dt;
  ContactHistory h;
  double delta = 0, w = u;  // the overlap and its rate
  Collision c;
  do {
    delta += w * dt;
    g.delta = delta, g.v_n = -w;
    const double f = evaluate(law, NoFriction{}, NoRolling{}, g, h).total.x;
    c.peak_force = std::max(c.peak_force, f);
    w -= f / m_eff * dt;
    c.duration += dt;
  } while (delta > 0);
  c.restitution = -w / u;
  return c;
}

TEST(ExampleLaw, HeadOnCollision) {
  const double d = 1e-3, m = kGlass.density * M_PI / 6 * d * d * d, m_eff = m / 2, r_eff = d / 4, u = 0.5;
  const HookeDashpot elastic = build(read("normal = \"hooke_dashpot\"\nstiffness = 1e4\n"));
  const double t_c = elastic.collision_time(m_eff, r_eff, u);
  EXPECT_DOUBLE_EQ(t_c, M_PI * std::sqrt(m_eff / 1e4));
  EXPECT_DOUBLE_EQ(elastic.peak_overlap(m_eff, r_eff, u), u * std::sqrt(m_eff / 1e4));
  const Collision free = head_on(elastic, m_eff, r_eff, u, t_c / 20000);
  EXPECT_NEAR(free.restitution, 1.0, 1e-3);
  EXPECT_NEAR(free.peak_force, u * std::sqrt(m_eff * 1e4), 1e-3 * u * std::sqrt(m_eff * 1e4));
  EXPECT_NEAR(free.duration, t_c, 1e-3 * t_c);
  // zeta = eta / (2 sqrt(m* k)) = 0.1: e = exp(-zeta pi / sqrt(1 - zeta^2)).
  const double eta = 0.2 * std::sqrt(m_eff * 1e4);
  ContactSpec spec = read("normal = \"hooke_dashpot\"\nstiffness = 1e4\n");
  spec.values.set("damping", eta);
  const Collision damped = head_on(build(spec), m_eff, r_eff, u, t_c / 20000);
  EXPECT_NEAR(damped.restitution, std::exp(-0.1 * M_PI / std::sqrt(0.99)), 1e-3);
}

}  // namespace
}  // namespace tsubu

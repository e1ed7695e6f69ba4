// The World's articulations: each link a driven body of the rigid bodies (dynamics/multibody.h)
// answered by the articulation's LinkResponse, and the link bodies moved after each step.
#include <memory>
#include <string>

#include "inertia/articulation/link_response.h"
#include "inertia/core/error.h"
#include "inertia/core/math.h"
#include "inertia/world/world.h"
#include "slots.h"

namespace inertia {

namespace {

void checkSettings(const WorldArticulationSettings& s) {
  const std::string what = "World::createArticulation '" + s.name + "': ";
  require(s.model.linkCount() > 0, what + "the model has no links");
  require(allFinite(s.base.p) && allFinite(s.base.q) && std::abs(s.base.q.norm() - 1) < Real(1e-3),
          what + "base must be finite with a unit quaternion");
  for (std::size_t k = 0; k < s.shapes.size(); ++k) {
    const LinkShapeSettings& shape = s.shapes[k];
    require(shape.link >= 0 && shape.link < s.model.linkCount(),
            what + "shapes[" + std::to_string(k) + "].link " + std::to_string(shape.link) +
                " is not a link of the model");
    require(shape.shape.type() != ShapeType::Plane && shape.shape.type() != ShapeType::HeightField,
            what + "shapes[" + std::to_string(k) + "]: planes and height fields cannot be links");
  }
}

}  // namespace

ArticulationId World::createArticulation(const WorldArticulationSettings& s) {
  checkSettings(s);
  auto art = std::make_unique<articulation::Articulation<Real>>(s.model, s.solver);
  if (s.q.size() > 0 || s.qd.size() > 0)
    art->setState(s.q.size() > 0 ? s.q : art->q(),
                  s.qd.size() > 0 ? s.qd : articulation::VectorX<Real>(art->qd()));
  auto response = std::make_unique<articulation::LinkResponse>(*art, s.base, settings_.gravity);
  std::vector<BodyId> links;
  for (int i = 0; i < s.model.linkCount(); ++i) {
    const articulation::Link<Real>& link = s.model.link(i);
    const Transform pose = response->linkPose(i);
    BodySettings body;
    body.type = BodyType::Dynamic;
    body.position = pose.p;
    body.orientation = pose.q;
    body.mass = link.mass;
    body.name = s.name + "/" + link.name;
    links.push_back(bodies_.createBody(body));
  }
  for (const LinkShapeSettings& shape : s.shapes)
    bodies_.addShape(links[std::size_t(shape.link)], shape.shape, shape.material, shape.pose);
  std::size_t index = 0;
  while (index < articulationSlots_.size() && articulationSlots_[index].articulation) ++index;
  if (index == articulationSlots_.size()) articulationSlots_.emplace_back();
  ArticulationSlot& slot = articulationSlots_[index];
  std::vector<int> parents;
  if (s.selfCollision)
    for (int i = 0; i < s.model.linkCount(); ++i) parents.push_back(s.model.link(i).parent);
  slot.group = bodies_.addMultibody(response.get(), links, parents);
  slot.articulation = std::move(art);
  slot.response = std::move(response);
  slot.links = std::move(links);
  slot.name = s.name;
  followArticulation(slot);
  return {std::uint32_t(index), slot.generation};
}

void World::destroyArticulation(ArticulationId id) {
  ArticulationSlot& slot = articulationSlot(id);
  bodies_.removeMultibody(slot.group);
  for (BodyId link : slot.links) bodies_.destroyBody(link);
  slot.articulation.reset();
  slot.response.reset();
  slot.links.clear();
  slot.name.clear();
  ++slot.generation;
}

bool World::isValid(ArticulationId id) const {
  return !id.isNull() && id.index < articulationSlots_.size() &&
         articulationSlots_[id.index].articulation &&
         articulationSlots_[id.index].generation == id.generation;
}

World::ArticulationSlot& World::articulationSlot(ArticulationId id) {
  require(isValid(id), "World: invalid articulation id (index " + std::to_string(id.index) + ")");
  return articulationSlots_[id.index];
}

const World::ArticulationSlot& World::articulationSlot(ArticulationId id) const {
  require(isValid(id), "World: invalid articulation id (index " + std::to_string(id.index) + ")");
  return articulationSlots_[id.index];
}

articulation::Articulation<Real>& World::articulation(ArticulationId id) {
  return *articulationSlot(id).articulation;
}

const articulation::Articulation<Real>& World::articulation(ArticulationId id) const {
  return *articulationSlot(id).articulation;
}

void World::syncArticulation(ArticulationId id) {
  ArticulationSlot& slot = articulationSlot(id);
  slot.response->updatePoses();
  followArticulation(slot);
}

std::string_view World::articulationName(ArticulationId id) const {
  return articulationSlot(id).name;
}

BodyId World::linkBody(ArticulationId id, int link) const {
  const ArticulationSlot& slot = articulationSlot(id);
  require(link >= 0 && std::size_t(link) < slot.links.size(),
          "World::linkBody: no link " + std::to_string(link));
  return slot.links[std::size_t(link)];
}

std::vector<ArticulationId> World::articulations() const {
  std::vector<ArticulationId> ids;
  for (std::uint32_t i = 0; i < articulationSlots_.size(); ++i)
    if (articulationSlots_[i].articulation) ids.push_back({i, articulationSlots_[i].generation});
  return ids;
}

// An articulation in a State: copies of the articulation and of its response, which answers
// for the copy, and the slot's bookkeeping.
struct World::SavedArticulation {
  std::unique_ptr<articulation::Articulation<Real>> articulation;
  std::unique_ptr<articulation::LinkResponse> response;
  std::vector<BodyId> links;
  int group = -1;
  std::string name;
};

void World::saveArticulations(State& state) const {
  for (const ArticulationSlot& slot : articulationSlots_) {
    std::shared_ptr<SavedArticulation> saved;
    if (slot.articulation) {
      saved = std::make_shared<SavedArticulation>();
      saved->articulation = std::make_unique<articulation::Articulation<Real>>(*slot.articulation);
      saved->response =
          std::make_unique<articulation::LinkResponse>(*slot.response, *saved->articulation);
      saved->links = slot.links;
      saved->group = slot.group;
      saved->name = slot.name;
      // The State's bodies answer to the State's response, not to this world's.
      state.bodies.setMultibodyResponse(slot.group, saved->response.get());
    }
    state.articulations.emplace_back(std::move(saved), slot.generation);
  }
}

// After the rigid bodies were restored: each slot as saved (a live articulation assigned in
// place), and each group of the restored bodies pointed at its slot's response, which the
// saved bodies knew by the address of the response of the world that saved them.
void World::restoreArticulations(const State& state) {
  detail::prepareRestoredSlots(articulationSlots_, &ArticulationSlot::articulation,
                               state.articulations.size());
  for (std::size_t i = 0; i < state.articulations.size(); ++i) {
    ArticulationSlot& slot = articulationSlots_[i];
    const auto& [saved, generation] = state.articulations[i];
    slot.generation = detail::restoredGeneration(saved != nullptr, generation, slot.generation,
                                                 slot.articulation != nullptr);
    if (!saved) {
      const std::uint32_t kept = slot.generation;
      slot = ArticulationSlot{};
      slot.generation = kept;
      continue;
    }
    if (slot.articulation)
      *slot.articulation = *saved->articulation;
    else
      slot.articulation = std::make_unique<articulation::Articulation<Real>>(*saved->articulation);
    slot.response =
        std::make_unique<articulation::LinkResponse>(*saved->response, *slot.articulation);
    slot.links = saved->links;
    slot.group = saved->group;
    slot.name = saved->name;
    bodies_.setMultibodyResponse(slot.group, slot.response.get());
  }
}

// The link bodies take the links' poses and velocities.
void World::followArticulation(const ArticulationSlot& slot) {
  for (std::size_t i = 0; i < slot.links.size(); ++i) {
    Vec3 v, w;
    slot.response->linkVelocity(int(i), v, w);
    bodies_.setDrivenState(slot.links[i], slot.response->linkPose(int(i)), v, w);
  }
}

}  // namespace inertia

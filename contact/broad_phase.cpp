#include "contact/broad_phase.hpp"

#include <fcl/broadphase/broadphase_dynamic_AABB_tree.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/narrowphase/collision_object.h>

#include <algorithm>

namespace ckpd {

struct BroadPhase::Tree {
  fcl::DynamicAABBTreeCollisionManagerd manager;
  std::vector<std::shared_ptr<fcl::Boxd>> shapes;
  std::vector<std::unique_ptr<fcl::CollisionObjectd>> objects;
  std::vector<std::size_t> body;  // per object
  bool registered = false;
};

BroadPhase::BroadPhase(const std::vector<std::size_t>& members) : tree_(std::make_unique<Tree>()) {
  for (std::size_t b : members) {
    auto shape = std::make_shared<fcl::Boxd>(1.0, 1.0, 1.0);
    auto object = std::make_unique<fcl::CollisionObjectd>(shape);
    tree_->body.push_back(b);
    // The user data is the body index, read back in the callback.
    object->setUserData(reinterpret_cast<void*>(static_cast<std::uintptr_t>(b)));
    tree_->shapes.push_back(std::move(shape));
    tree_->objects.push_back(std::move(object));
  }
}

BroadPhase::~BroadPhase() = default;

namespace {

using PairList = std::vector<std::pair<std::uint32_t, std::uint32_t>>;

// Called by FCL for every pair of objects whose boxes overlap; no narrow-phase geometry test:
// the boxes are all we ask about.
bool record_pair(fcl::CollisionObjectd* a, fcl::CollisionObjectd* b, void* data) {
  auto* pairs = static_cast<PairList*>(data);
  auto ia = static_cast<std::uint32_t>(reinterpret_cast<std::uintptr_t>(a->getUserData()));
  auto ib = static_cast<std::uint32_t>(reinterpret_cast<std::uintptr_t>(b->getUserData()));
  if (ia > ib) std::swap(ia, ib);
  pairs->emplace_back(ia, ib);
  return false;  // keep going
}

}  // namespace

PairList BroadPhase::overlapping_pairs(const std::vector<Box3>& boxes) {
  PairList pairs;
  overlapping_pairs(boxes, pairs);
  return pairs;
}

void BroadPhase::overlapping_pairs(const std::vector<Box3>& boxes, PairList& pairs) {
  Tree& t = *tree_;
  for (std::size_t k = 0; k < t.objects.size(); ++k) {
    const Box3& box = boxes[t.body[k]];
    t.shapes[k]->side = box.hi - box.lo;
    t.shapes[k]->computeLocalAABB();
    t.objects[k]->setTranslation(0.5 * (box.lo + box.hi));
    t.objects[k]->computeAABB();
  }
  if (!t.registered) {
    std::vector<fcl::CollisionObjectd*> raw;
    for (auto& o : t.objects) raw.push_back(o.get());
    t.manager.registerObjects(raw);
    t.manager.setup();
    t.registered = true;
  } else {
    t.manager.update();
  }
  pairs.clear();
  t.manager.collide(&pairs, record_pair);
  std::sort(pairs.begin(), pairs.end());
}

}  // namespace ckpd

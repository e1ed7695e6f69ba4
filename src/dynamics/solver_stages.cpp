#include "solver_stages.h"

#include <algorithm>
#include <chrono>
#include <numeric>

#include "inertia/core/math.h"
#include "integrate.h"
#include "joint_solver.h"
#include "lcp_contact.h"
#include "multibody_contacts.h"

namespace inertia::detail {

using Data = RigidBodyData;

namespace {

// The runaway guard's bound (guardRunaways), in multiples of a body's speed caps (400 m/s and
// 200 rad/s by default).
constexpr Real kRunaway = 1000;

// The solver body of body slot `bi`, made on first use (-1 for a static body): the slots are
// numbered in the order of the contacts, whatever the number of workers.
int solverSlot(Data& D, std::uint32_t bi) {
  if (D.bodies[bi].type == BodyType::Static) return -1;
  if (D.solverIndex[bi] < 0) {
    D.solverIndex[bi] = static_cast<int>(D.solverToBody.size());
    D.solverToBody.push_back(bi);
  }
  return D.solverIndex[bi];
}

// A side of a driven joint: the world, a group's point, or a solver body (-1: static).
MultibodySide jointSide(Data& D, std::uint32_t bi) {
  if (bi == kWorldBody) return {};
  if (D.bodies[bi].group >= 0) return {-1, D.bodies[bi].group};
  D.wake(D.bodies[bi]);  // hung from a link, which never sleeps
  return {solverSlot(D, bi), -1};
}

// The joints with a driven body on a side (a link's: always awake), out of the graph
// (multibody_contacts.h); the rigid body on the other side gets a solver body.
void addMultibodyJoints(Data& D) {
  D.multibodyJoints.clear();
  for (std::uint32_t ji = 0; ji < D.joints.size(); ++ji) {
    const JointRecord& j = D.joints[ji];
    if (!j.alive || !j.enabled || !drivenJoint(D, j)) continue;
    MultibodyJoint& m = D.multibodyJoints.emplace_back();
    m.joint = ji;
    m.a = jointSide(D, j.bodyA);
    m.b = jointSide(D, j.bodyB);
  }
}

// The velocities, masses and start poses of the solver bodies.
void prepareSolverBodies(Data& D, StepWorkers& workers) {
  const std::size_t n = D.solverToBody.size();
  D.solverBodies.resize(n);
  D.startRotation.resize(n);
  D.startCom.resize(n);
  workers.parallelFor(n, [&](std::size_t first, std::size_t last) {
    for (std::size_t k = first; k < last; ++k) {
      const BodyRecord& b = D.bodies[D.solverToBody[k]];
      SolverBody sb;
      sb.v = b.v;
      sb.w = b.w;
      sb.invMass = b.invMass;
      sb.invInertia = b.invInertiaWorld();
      D.solverBodies[k] = sb;
      D.startRotation[k] = b.pose.q;
      D.startCom[k] = b.com;
    }
  });
}

// One contact's constraint: anchors, friction axes, materials and last step's impulses.
void prepareContact(Data& D, const DynamicsSettings& s, ContactConstraint& c, const Softness& soft,
                    const Softness& staticSoft) {
  const std::size_t ci = static_cast<std::size_t>(c.contactIndex);
  ContactInfo& info = D.contacts[ci];
  const BodyRecord& ba = D.bodies[info.bodyA.index];
  const BodyRecord& bb = D.bodies[info.bodyB.index];
  const Material& ma = D.frames[info.shapeA.index].material;
  const Material& mb = D.frames[info.shapeB.index].material;
  const Real staticFriction = combine(s.combine.friction, ma.friction, mb.friction);
  const Real slidingFriction = combine(s.combine.friction, ma.sliding(), mb.sliding());
  c.restitution = combine(s.combine.restitution, ma.restitution, mb.restitution);
  c.rolling = combine(s.combine.rollingFriction, ma.rollingFriction, mb.rollingFriction);
  c.spinning = combine(s.combine.spinningFriction, ma.spinningFriction, mb.spinningFriction);
  c.softness = (ba.invMass == 0 || bb.invMass == 0) ? staticSoft : soft;
  c.normal = info.manifold.normal;
  c.pointCount = info.manifold.pointCount;
  // Friction axes: along the sliding direction when sliding (as Jolt does), so the disc
  // clamp of the two rows' impulse opposes the sliding velocity even though the rows'
  // effective masses differ; otherwise a basis of the normal alone.
  // The anchors and the points' relative velocities first: the slip direction needs them all.
  std::array<Vec3, 4> dvs;
  Vec3 slip = Vec3::Zero();
  for (int k = 0; k < c.pointCount; ++k) {
    const ContactPoint& cp = info.manifold.points[static_cast<std::size_t>(k)];
    ConstraintPoint& p = c.points[static_cast<std::size_t>(k)];
    const Vec3 mid = Real(0.5) * (cp.pointA + cp.pointB);
    p.rA = mid - ba.com;
    p.rB = mid - bb.com;
    dvs[std::size_t(k)] = bb.v + bb.w.cross(p.rB) - ba.v - ba.w.cross(p.rA);
    slip += dvs[std::size_t(k)];
  }
  slip -= slip.dot(c.normal) * c.normal;
  const Real slipNorm = slip.norm() / Real(c.pointCount);
  if (slipNorm > kStickSpeed) {
    c.tangent[0] = slip.normalized();
    c.tangent[1] = c.normal.cross(c.tangent[0]);
  } else {
    c.tangent = tangentBasis(c.normal);
  }
  const ContactExtra& extra = D.extras[ci];
  Real tangentialSpeed2 = 0;  // the largest, squared
  for (int k = 0; k < c.pointCount; ++k) {
    const ContactPoint& cp = info.manifold.points[static_cast<std::size_t>(k)];
    ConstraintPoint& p = c.points[static_cast<std::size_t>(k)];
    p.adjustedSeparation = cp.separation - (p.rB - p.rA).dot(c.normal);
    p.normalImpulse = info.normalImpulses[static_cast<std::size_t>(k)];
    for (int t = 0; t < 2; ++t)
      p.tangentImpulse[t] = extra.tangentImpulse[static_cast<std::size_t>(k)].dot(c.tangent[t]);
    const Vec3& dv = dvs[std::size_t(k)];
    p.relativeVelocity = dv.dot(c.normal);
    p.launch = c.restitution * std::max(-p.relativeVelocity, Real(0));
    tangentialSpeed2 =
        std::max(tangentialSpeed2, (dv - p.relativeVelocity * c.normal).squaredNorm());
  }
  c.friction = tangentialSpeed2 < kStickSpeed * kStickSpeed ? staticFriction : slidingFriction;
  for (int t = 0; t < 2; ++t) c.rollingImpulse[t] = extra.angularImpulse.dot(c.tangent[t]);
  c.spinningImpulse = extra.angularImpulse.dot(c.normal);
}

// What a substep's velocity and position updates need of each solver body's record.
void prepareMotion(Data& D, const DynamicsSettings& s, Real h, StepWorkers& workers) {
  D.motion.resize(D.solverBodies.size());
  workers.parallelFor(D.solverBodies.size(), [&](std::size_t first, std::size_t last) {
    for (std::size_t k = first; k < last; ++k) {
      const BodyRecord& b = D.bodies[D.solverToBody[k]];
      Data::SubstepMotion& m = D.motion[k];
      m.dynamic = b.type == BodyType::Dynamic;
      m.dv = h * (b.gravityScale * s.gravity + b.invMass * b.force);
      m.dw = h * (D.solverBodies[k].invInertia * b.torque);
      m.linearFactor = 1 / (1 + h * b.linearDamping);
      m.angularFactor = 1 / (1 + h * b.angularDamping);
      m.maxLinearSpeed = b.maxLinearSpeed;
      m.maxAngularSpeed = b.maxAngularSpeed;
      // w x (I w) vanishes for a sphere's or a cube's inertia (c * identity); the implicit
      // step would only add its rounding.
      m.gyroscopic = !b.isotropic;
    }
  });
}

// Between a pass's iterations, a body faster than kRunaway times its speed caps is brought
// back to that: a guard against float's range, not a cap (the caps act before each velocity
// and position update, and a sane scene never meets this bound: its bytes do not change). The
// world fuzz target found bodies of micrograms or micrometres (inverse inertia up to 1e17)
// whose rows hold those inverse masses beside a heavy body's: K^-1 carries the rounding of K's
// largest entries, and each iteration multiplied the body's speed (1e7 rad/s by the third, or
// 3e9 in the first) until it overflowed to NaN within one substep (inputs
// world-sliver-jointed-100km-away-nan, world-sliver-and-spinning-tree-contact-nan). Bounded at
// each iteration's start, the runaway stays finite, and the position update's caps end it.
// One pass over the solver bodies per iteration but the last.
void guardRunaways(Data& D) {
  for (std::size_t k = 0; k < D.solverBodies.size(); ++k) {
    const Data::SubstepMotion& m = D.motion[k];
    if (!m.dynamic) continue;  // a kinematic body keeps the velocity it is given
    capSpeed(D.solverBodies[k].v, kRunaway * m.maxLinearSpeed);
    capSpeed(D.solverBodies[k].w, kRunaway * m.maxAngularSpeed);
  }
}

// Velocities of the constrained bodies, from their capped speeds: gravity, forces, damping,
// implicit gyroscopic term.
void integrateVelocities(Data& D, Real h, StepWorkers& workers) {
  workers.parallelFor(D.solverBodies.size(), [&](std::size_t first, std::size_t last) {
    for (std::size_t k = first; k < last; ++k) {
      const Data::SubstepMotion& m = D.motion[k];
      SolverBody& sb = D.solverBodies[k];
      if (!m.dynamic) continue;
      // From capped speeds, as the positions move: the previous substep's solve and relax
      // passes can leave any (a sliver struck by a link that a spinning hull threw), and the
      // gyroscopic term's products overflowed from there.
      capSpeed(sb.v, m.maxLinearSpeed);
      capSpeed(sb.w, m.maxAngularSpeed);
      sb.v += m.dv;
      sb.v *= m.linearFactor;
      sb.w += m.dw;
      if (m.gyroscopic) {
        const Quat q = (sb.dq * D.startRotation[k]).normalized();
        sb.w = implicitGyroscopic(q, D.bodies[D.solverToBody[k]].inertiaLocal, sb.w, h);
      }
      sb.w *= m.angularFactor;
    }
  });
}

// The bodies' motion since the step's start, after the speed caps.
void integratePositions(Data& D, Real h, StepWorkers& workers) {
  workers.parallelFor(D.solverBodies.size(), [&](std::size_t first, std::size_t last) {
    for (std::size_t k = first; k < last; ++k) {
      const Data::SubstepMotion& m = D.motion[k];
      SolverBody& sb = D.solverBodies[k];
      capSpeed(sb.v, m.maxLinearSpeed);
      capSpeed(sb.w, m.maxAngularSpeed);
      sb.dp += h * sb.v;
      sb.dq = integrateRotation(sb.dq, sb.w, h);
      sb.dR = sb.dq.toRotationMatrix();
    }
  });
}

// Joints per block of a colour's parallel pass.
constexpr std::size_t kJointGrain = 16;

// Runs a pass colour by colour (Box2D v3's solver stages): joint(k) for each joint constraint
// of the colour, then contacts(first, count) for its bundles. A colour's joints and bundles
// share no moving body, so the workers take blocks of both at once with the result of the
// sequence; the overflow group runs in sequence, its joints before its contacts.
template <class JointFn, class ContactFn>
void forEachColor(Data& D, StepWorkers& workers, JointFn joint, ContactFn contacts) {
  const ConstraintColoring& col = D.coloring;
  for (std::size_t g = 0; g < D.bundles.groupCount(); ++g) {
    const std::uint32_t jointBegin = col.jointOffsets[g], jointEnd = col.jointOffsets[g + 1];
    const std::uint32_t bundleBegin = D.bundles.groupBegin(g), bundleEnd = D.bundles.groupEnd(g);
    if (D.bundles.sequentialGroup(g)) {
      for (std::uint32_t k = jointBegin; k < jointEnd; ++k) joint(col.jointOrder[k]);
      contacts(bundleBegin, std::size_t(bundleEnd - bundleBegin));
      continue;
    }
    const std::size_t jointBlocks = (jointEnd - jointBegin + kJointGrain - 1) / kJointGrain;
    const std::size_t bundleBlocks = (bundleEnd - bundleBegin + kBundleGrain - 1) / kBundleGrain;
    workers.parallelFor(jointBlocks + bundleBlocks, 1, [&](std::size_t first, std::size_t last) {
      for (std::size_t block = first; block < last; ++block) {
        if (block < jointBlocks) {
          const std::uint32_t begin = jointBegin + std::uint32_t(block * kJointGrain);
          const std::uint32_t end = std::min(jointEnd, begin + std::uint32_t(kJointGrain));
          for (std::uint32_t k = begin; k < end; ++k) joint(col.jointOrder[k]);
        } else {
          const std::uint32_t begin =
              bundleBegin + std::uint32_t((block - jointBlocks) * kBundleGrain);
          contacts(begin, std::min<std::size_t>(kBundleGrain, bundleEnd - begin));
        }
      }
    });
  }
}

void warmStart(Data& D, int stamp, Real h, Real flight, StepWorkers& workers) {
  D.bundles.updateApproach(D.solverBodies, h, flight, workers);
  forEachColor(
      D, workers,
      [&](std::uint32_t k) { warmStartJoint(D, D.jointConstraints[k], D.solverBodies, stamp); },
      [&](std::uint32_t first, std::size_t count) {
        D.bundles.warmStart(D.solverBodies.data(), first, count);
      });
  warmStartMultibodyJoints(D, stamp);
  warmStartMultibodyContacts(D);
}

void solve(Data& D, const BiasMode& mode, const JointPass& jointPass, int iterations,
           StepWorkers& workers) {
  for (int it = 0; it < iterations; ++it) {
    solveJointTrees(D, jointPass, it == 0, workers);
    forEachColor(
        D, workers,
        [&](std::uint32_t k) { solveJoint(D, D.jointConstraints[k], D.solverBodies, jointPass); },
        [&](std::uint32_t first, std::size_t count) {
          D.bundles.solve(D.solverBodies.data(), mode, first, count);
        });
    // The joints and contacts on driven bodies, then the groups' own rows, in sequence after
    // the colours (multibody_contacts.h).
    solveMultibodyJoints(D, jointPass);
    solveMultibodyContacts(D, mode);
    solveMultibodyRows(D);
    if (it + 1 < iterations) guardRunaways(D);
  }
}

// soft_step's relaxation: the solve passes without the position bias (relaxMode.useBias off).
void relax(Data& D, const BiasMode& relaxMode, const JointPass& jointPass, int iterations,
           StepWorkers& workers) {
  solve(D, relaxMode, jointPass, iterations, workers);
}

// An island the LCP does not take: `iterations` pgs passes over its joints, then its contacts,
// warm started (the contacts on copies, as solveContactsLcp's fallback).
void solveIslandPgs(Data& D, std::span<const std::uint32_t> island, const BiasMode& rigid,
                    const JointPass& jointPass, int iterations) {
  const std::size_t contactCount = D.constraints.size();
  std::vector<ContactConstraint>& contacts = D.lcp.scratch;
  contacts.clear();
  for (std::uint32_t k : island)
    if (k < contactCount) contacts.push_back(D.constraints[k]);
  warmStart(contacts, D.solverBodies);
  for (std::uint32_t k : island)
    if (k >= contactCount)
      warmStartJoint(D, D.jointConstraints[k - contactCount], D.solverBodies, jointPass.stamp);
  for (int it = 0; it < iterations; ++it) {
    for (std::uint32_t k : island)
      if (k >= contactCount)
        solveJoint(D, D.jointConstraints[k - contactCount], D.solverBodies, jointPass);
    solve(contacts, D.solverBodies, rigid);
  }
  std::size_t next = 0;
  for (std::uint32_t k : island)
    if (k < contactCount) D.constraints[k] = contacts[next++];
}

// With the LCP solvers each island of contacts and joints (linked through shared solver
// bodies) is one LCP: the contacts' rows as solveContactsLcp makes them and the joints' rows
// (appendJointLcpRows: bilateral locked rows, one-sided limits, boxed motors and friction,
// springs through a compliance). An island too large for a direct solve, or whose LCP fails,
// takes the pgs iterations instead.
void solveIslandsLcp(Data& D, const BiasMode& mode, const JointPass& jointPass, LcpMethod method,
                     int iterations) {
  BiasMode rigid = mode;
  rigid.soft = false;
  LcpWorkspace& ws = D.lcp;
  const std::size_t contactCount = D.constraints.size();
  const ConstraintIslands& islands = D.lcpIslands;
  for (std::size_t i = 0; i + 1 < islands.offsets.size(); ++i) {
    const std::span<const std::uint32_t> island(islands.constraints.data() + islands.offsets[i],
                                                islands.offsets[i + 1] - islands.offsets[i]);
    ws.rows.clear();
    int groups = 0;
    for (std::uint32_t k : island) {
      if (k < contactCount)
        appendContactRows(D.constraints[k], int(k), D.solverBodies, rigid, ws.rows, groups);
      else
        appendJointLcpRows(D, D.jointConstraints[k - contactCount], D.solverBodies, jointPass,
                           ws.rows, groups);
    }
    if (solveLcpRows(ws.rows, D.constraints, D.solverBodies, method, ws.impulses, nullptr))
      applyLcpImpulses(ws.rows, ws.impulses, D.constraints, D.solverBodies);
    else
      solveIslandPgs(D, island, rigid, jointPass, iterations);
  }
  // The joints and contacts on driven bodies and the groups' own rows are not in the LCPs: pgs
  // passes after them.
  warmStartMultibodyJoints(D, jointPass.stamp);
  warmStartMultibodyContacts(D);
  for (int it = 0; it < iterations; ++it) {
    solveMultibodyJoints(D, jointPass);
    solveMultibodyContacts(D, rigid);
    solveMultibodyRows(D);
  }
}

// The impulses into the contacts, for the next step's warm start and for the user.
void storeImpulses(Data& D, StepWorkers& workers) {
  workers.parallelFor(D.constraints.size(), [&](std::size_t first, std::size_t last) {
    for (std::size_t ci = first; ci < last; ++ci) {
      const ContactConstraint& c = D.constraints[ci];
      ContactInfo& info = D.contacts[static_cast<std::size_t>(c.contactIndex)];
      ContactExtra& extra = D.extras[static_cast<std::size_t>(c.contactIndex)];
      // A contact that pushed during the step touched, even if it began speculative; its
      // approach speed is the one measured just before the impact (updateApproach).
      extra.approach = 0;
      for (int k = 0; k < c.pointCount; ++k) {
        const ConstraintPoint& p = c.points[static_cast<std::size_t>(k)];
        if (p.maxNormalImpulse > 0) extra.touching = true;
        extra.approach = std::max(extra.approach, -p.relativeVelocity);
        info.normalImpulses[static_cast<std::size_t>(k)] = p.normalImpulse;
        extra.tangentImpulse[static_cast<std::size_t>(k)] =
            p.tangentImpulse[0] * c.tangent[0] + p.tangentImpulse[1] * c.tangent[1];
      }
      extra.angularImpulse = c.rollingImpulse[0] * c.tangent[0] +
                             c.rollingImpulse[1] * c.tangent[1] + c.spinningImpulse * c.normal;
    }
  });
}

bool isLcp(const DynamicsSettings& s) {
  return s.solver.type == SolverType::LcpDantzig || s.solver.type == SolverType::LcpLemke;
}

// The lag c / a of the free flight's method, whose modified energy under a constant
// acceleration a is v^2 - 2 a y + a c v (updateApproachSlice): h for the methods that update
// the position with the new velocity, -h for explicit Euler, which uses the old one, and 0 for
// the methods exact under a constant acceleration.
Real flightLag(ode::Method method, Real h) {
  switch (method) {
    case ode::Method::SymplecticEuler:
    case ode::Method::BackwardEuler:
      return h;
    case ode::Method::ExplicitEuler:
      return -h;
    default:
      return 0;
  }
}

}  // namespace

void prepareContacts(Data& D, const DynamicsSettings& s, Real dt, StepWorkers& workers) {
  const ContactTuning& tuning = s.contact;
  D.solverIndex.assign(D.bodies.size(), -1);
  D.solverToBody.clear();
  // The constraints, their solver bodies and graph edges in contact order, in sequence (cheap);
  // the rest of each constraint in parallel.
  D.constraints.clear();
  D.contactEdges.clear();
  D.multibodyContacts.clear();
  for (std::size_t ci = 0; ci < D.contacts.size(); ++ci) {
    const ContactInfo& info = D.contacts[ci];
    const BodyRecord& ba = D.bodies[info.bodyA.index];
    const BodyRecord& bb = D.bodies[info.bodyB.index];
    const bool aActive = ba.type == BodyType::Dynamic && ba.awake;
    const bool bActive = bb.type == BodyType::Dynamic && bb.awake;
    if (!aActive && !bActive) continue;
    if (ba.group >= 0 || bb.group >= 0) {
      // A driven body's contact: its own stage (multibody_contacts.h), out of the graph.
      MultibodyContact& m = D.multibodyContacts.emplace_back();
      m.contactIndex = static_cast<int>(ci);
      m.a = ba.group >= 0 ? MultibodySide{-1, ba.group}
                          : MultibodySide{solverSlot(D, info.bodyA.index), -1};
      m.b = bb.group >= 0 ? MultibodySide{-1, bb.group}
                          : MultibodySide{solverSlot(D, info.bodyB.index), -1};
      continue;
    }
    ContactConstraint& c = D.constraints.emplace_back();
    c.contactIndex = static_cast<int>(ci);
    c.bodyA = solverSlot(D, info.bodyA.index);
    c.bodyB = solverSlot(D, info.bodyB.index);
    D.contactEdges.push_back({c.bodyA, c.bodyB});
  }
  addMultibodyJoints(D);
  addJointEdges(D, [&](std::uint32_t bi) { return solverSlot(D, bi); });
  prepareSolverBodies(D, workers);
  const Real h = dt / Real(s.substeps);
  const Real hertz = std::min(tuning.hertz, Real(0.25) / h);
  const Softness soft = makeSoft(hertz, tuning.dampingRatio, h);
  const Softness staticSoft = makeSoft(2 * hertz, tuning.dampingRatio, h);
  prepareMultibodyContacts(D, s, soft, staticSoft);
  // The graph's colours (from the edges alone) on one worker while the others prepare the
  // constraints.
  const bool lcp = isLcp(s);
  const std::size_t count = D.constraints.size();
  workers.parallelForBeside(
      [&] {
        if (!lcp) colorGraph(D.jointEdges, D.contactEdges, D.solverBodies, D.coloring);
      },
      count, workers.grainFor(count, 32),
      [&](std::size_t first, std::size_t last) {
        for (std::size_t k = first; k < last; ++k)
          prepareContact(D, s, D.constraints[k], soft, staticSoft);
      });
  if (lcp) {
    prepareJoints(D, {}, workers);
    for (ContactConstraint& c : D.constraints) {
      const SolverBody none{};
      const SolverBody& a = c.bodyA >= 0 ? D.solverBodies[static_cast<std::size_t>(c.bodyA)] : none;
      const SolverBody& b = c.bodyB >= 0 ? D.solverBodies[static_cast<std::size_t>(c.bodyB)] : none;
      computeMasses(c, a, b);
    }
    // One island list over the contacts, then the joints (index - contacts).
    D.lcpEdges.assign(D.contactEdges.begin(), D.contactEdges.end());
    D.lcpEdges.insert(D.lcpEdges.end(), D.jointEdges.begin(), D.jointEdges.end());
    groupConstraints(D.lcpEdges, D.solverBodies.size(), D.lcpIslands);
  } else {
    // The joint constraints are made in colour order, so that each colour's pass reads them
    // in sequence (in edge order each joint of a large grid cost a cache miss or two).
    prepareJoints(D, D.coloring.jointOrder, workers);
    std::iota(D.coloring.jointOrder.begin(), D.coloring.jointOrder.end(), 0u);
    buildJointTrees(D);
    // The bundles compute the masses themselves, a bundle at a time.
    D.bundles.build(D.constraints, D.solverBodies, D.coloring, workers);
  }
  prepareMotion(D, s, h, workers);
}

double solveSubsteps(Data& D, const DynamicsSettings& s, Real dt, StepWorkers& workers) {
  using Clock = std::chrono::steady_clock;
  const ContactTuning& tuning = s.contact;
  const Real h = dt / Real(s.substeps);
  const bool lcp = isLcp(s);
  const bool softStep = s.solver.type == SolverType::SoftStep;
  const LcpMethod lcpMethod =
      s.solver.type == SolverType::LcpLemke ? LcpMethod::Lemke : LcpMethod::Dantzig;
  BiasMode mode;
  mode.soft = softStep;
  mode.invH = 1 / h;
  mode.pushVelocity = tuning.pushVelocity;
  mode.baumgarte = tuning.baumgarte;
  mode.linearSlop = tuning.linearSlop;
  BiasMode relaxMode = mode;
  relaxMode.useBias = false;
  JointPass jointSolve = jointPass(s, h, true);
  JointPass jointRelax = jointPass(s, h, false);
  const Real flight = flightLag(s.integrator, h);
  double integrationTime = 0;
  for (int sub = 0; sub < s.substeps; ++sub) {
    // A joint's rows are made once per position update: the relaxation's, after this
    // substep's, serve the next substep's warm start and solve (velocity updates leave the
    // positions alone).
    jointSolve.stamp = sub;
    jointRelax.stamp = sub + 1;
    // The normal velocities before the velocity update, for the approach speed at impact.
    if (lcp)
      beginApproach(D.constraints, D.solverBodies);
    else
      D.bundles.beginApproach(D.solverBodies, workers);
    auto ti = Clock::now();
    integrateVelocities(D, h, workers);
    integrateMultibodyVelocities(D, h, workers);
    integrationTime += std::chrono::duration<double>(Clock::now() - ti).count();
    if (lcp) {
      // Direct LCP per island in place of the warm start and iterations (lcp_contact.h).
      updateApproach(D.constraints, D.solverBodies, h, flight);
      solveIslandsLcp(D, mode, jointSolve, lcpMethod, s.solver.iterations);
    } else {
      warmStart(D, jointSolve.stamp, h, flight, workers);
      solve(D, mode, jointSolve, s.solver.iterations, workers);
    }
    ti = Clock::now();
    integratePositions(D, h, workers);
    integrateMultibodyPositions(D, h, workers);
    integrationTime += std::chrono::duration<double>(Clock::now() - ti).count();
    if (!lcp) projectJointTrees(D, jointRelax, workers);
    if (!lcp) D.bundles.updateMotion(D.solverBodies, workers);
    if (softStep) relax(D, relaxMode, jointRelax, s.solver.relaxIterations, workers);
  }
  if (lcp) {
    applyRestitution(D.constraints, D.solverBodies, tuning.restitutionThreshold);
  } else {
    D.bundles.applyRestitution(D.solverBodies, tuning.restitutionThreshold, workers);
    D.bundles.store(D.constraints, workers);
  }
  restituteMultibodyContacts(D, tuning.restitutionThreshold);
  storeImpulses(D, workers);
  storeMultibodyContacts(D);
  storeMultibodyJoints(D, h);
  storeJoints(D, h, workers);
  return integrationTime;
}

}  // namespace inertia::detail

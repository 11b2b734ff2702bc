"""Helpers of the MuJoCo coupling (``contact_sim.coupling.mujoco``) on a model's bodies and
damping: whether a body can move, whether a geom's contact direction can turn with its body,
whether the integrator takes velocity-dependent forces on a pair's kinematic trees implicitly,
and the joint damping's rate along a pair's normal.  Units: SI.
"""
import mujoco
import numpy as np


def normal_damping(pair, rate, w_n):
    """The joint damping's rate (1/s) on the gap's rate along the normal: c = rᵀ D r / w with
    r = M⁻¹ Jᵀ n (``rate``) and w = n J M⁻¹ Jᵀ n."""
    return float(rate @ (pair.damping * rate)) / w_n if pair.damped else 0.0


def damped(model, trees):
    """Whether MuJoCo's integrator takes velocity-dependent forces on these kinematic trees
    implicitly (its velocity update is then not M⁻¹ of the forces): joint damping (Euler,
    implicit, implicitfast), and under implicit and implicitfast tendon damping, fluid forces
    and actuators whose force depends on velocity; implicit's Coriolis derivatives too."""
    dofs = [i for i in range(model.nv) if int(model.dof_treeid[i]) in trees]
    if any(model.dof_damping[i] > 0.0 for i in dofs):
        return True
    integrator = int(model.opt.integrator)
    if integrator == int(mujoco.mjtIntegrator.mjINT_EULER):
        return False
    if integrator == int(mujoco.mjtIntegrator.mjINT_IMPLICIT):
        return True
    velocity_gain = (model.actuator_gaintype == int(mujoco.mjtGain.mjGAIN_AFFINE)) & (
        model.actuator_gainprm[:, 2] != 0.0)
    velocity_bias = (model.actuator_biastype == int(mujoco.mjtBias.mjBIAS_AFFINE)) & (
        model.actuator_biasprm[:, 2] != 0.0)
    return bool(np.any(velocity_gain | velocity_bias) or np.any(model.tendon_damping > 0.0)
                or model.opt.density > 0.0 or model.opt.viscosity > 0.0)


def moves(model, body):
    """Whether the body or one of its ancestors has a degree of freedom."""
    while body > 0:
        if model.body_dofnum[body] > 0:
            return True
        body = int(model.body_parentid[body])
    return False


def turns(model, geom):
    """Whether the generalized direction n J of a contact on ``geom`` can turn with its body:
    False for a geom on a body that does not move, and for a sphere centred on the centre of mass
    of a free body (its contact point's offset from the centre of mass lies along the normal, so
    a push there gives the same momenta at any orientation)."""
    body = int(model.geom_bodyid[geom])
    if not moves(model, body):
        return False
    joint = int(model.body_jntadr[body])
    free = (int(model.body_jntnum[body]) == 1 and int(model.body_parentid[body]) == 0
            and int(model.jnt_type[joint]) == int(mujoco.mjtJoint.mjJNT_FREE))
    centred = bool(np.all(model.geom_pos[geom] == model.body_ipos[body]))
    return not (free and centred and int(model.geom_type[geom]) == int(mujoco.mjtGeom.mjGEOM_SPHERE))

"""Commissioning overlays of the 3-D view: the set-point ghost and the forces of the physics.

:class:`SetPointGhost` draws the bodies the driven axes move a second time, translucent, where
the axes' set points would put them: the gap between ghost and machine is the following error,
and during a move the ghost runs ahead to where the move is going. The pose comes from forward
kinematics of a scratch ``MjData``: the axis joints at their set points, every other joint as
measured.

:class:`ContactOverlay` draws the forces with a small sphere at the point of action and an arrow
along the force, scaled to a readable length: every active contact (``data.contact``, its normal
force from ``mj_contactForce``; :func:`contact_forces`) and the forces that act at a place
without a contact (:func:`constraint_forces`): hard stops (active limits of slide joints) and
tendons under load (spring plus length limit, e.g. a press tool on its part). It draws at most
:data:`MAX_CONTACTS` contacts and :data:`MAX_CONSTRAINT_FORCES` stop and tendon forces (these
with a label of their magnitude, drawn over the machine: a stop sits inside a carriage, a tool in
its part) in a bounded number of reused scene nodes, whatever happens in the simulation. The
simulation thread takes both out of the live ``MjData`` for each snapshot.
"""

from __future__ import annotations

__all__ = [
    "CONSTRAINT_COLOR",
    "CONTACT_COLOR",
    "CONTACT_FIELDS",
    "CONTACT_POINT_SIZE",
    "DEFAULT_FORCE_SCALE",
    "FORCE_SCALES",
    "GHOST_COLOR",
    "GHOST_OPACITY",
    "LIMIT_JOINT",
    "LIMIT_TENDON",
    "MAX_CONSTRAINT_FORCES",
    "MAX_CONTACTS",
    "SLIDE",
    "ContactOverlay",
    "ForceMarks",
    "GhostAxis",
    "SetPointGhost",
    "constraint_forces",
    "contact_forces",
    "force_text",
    "ghost_axes",
    "moved_bodies",
    "tendon_spring_forces",
]

from collections.abc import Sequence
from dataclasses import dataclass

import mujoco
import numpy as np
import numpy.typing as npt
import viser

import scenes
from scenes.definition import unit_and_scale
from viewer.view3d.model_scene import ModelScene

GHOST_COLOR = (0.15, 0.75, 0.95)
"""Colour of the set-point ghost (cyan), RGB in [0, 1]."""

GHOST_OPACITY = 0.35
"""Opacity of the set-point ghost."""

MAX_CONTACTS = 64
"""Contacts drawn at most (the first ones of ``data.contact``)."""

CONTACT_COLOR = (255, 60, 20)
"""Colour of the contact points and force arrows (RGB in [0, 255])."""

MAX_CONSTRAINT_FORCES = 16
"""Joint-limit and tendon forces drawn at most."""

CONSTRAINT_COLOR = (200, 40, 230)
"""Colour of the hard-stop and tendon force marks (violet, RGB in [0, 255])."""

CONTACT_POINT_SIZE = 0.012
"""Diameter [m] of the sphere drawn at a contact point."""

FORCE_SCALES = {"1 mm/N": 1e-3, "0.1 mm/N": 1e-4, "0.01 mm/N": 1e-5, "0.001 mm/N": 1e-6}
"""Arrow lengths the viewer offers: label → arrow length per newton of force [m/N]."""

DEFAULT_FORCE_SCALE = "0.1 mm/N"
"""The arrow scale shown first: 1 kN draws a 100 mm arrow."""

CONTACT_FIELDS = 6
"""Columns of a contact row: contact point (x, y, z) [m], normal force vector (x, y, z) [N]."""


def contact_forces(
    model: mujoco.MjModel, data: mujoco.MjData, limit: int = MAX_CONTACTS
) -> npt.NDArray[np.float64]:
    """The active contacts of a simulation state, with their normal forces.

    Args:
        model: The compiled model.
        data: Its state after a step (``data.contact`` and the constraint forces current).
        limit: Contacts returned at most (the first ones).

    Returns:
        One row per contact, shape (n, :data:`CONTACT_FIELDS`): the contact point in world
        coordinates [m], then the normal force vector [N] in world coordinates, the force the
        contact's first geom exerts on its second (along the contact normal, from geom1 to geom2).
    """
    n = min(int(data.ncon), max(int(limit), 0))
    rows = np.zeros((n, CONTACT_FIELDS))
    wrench = np.zeros(6)
    for i in range(n):
        contact = data.contact[i]
        mujoco.mj_contactForce(model, data, i, wrench)
        rows[i, :3] = contact.pos
        rows[i, 3:] = wrench[0] * contact.frame[:3]
    return rows


LIMIT_JOINT = int(mujoco.mjtConstraint.mjCNSTR_LIMIT_JOINT)
"""``efc_type`` of a joint-limit constraint row."""

LIMIT_TENDON = int(mujoco.mjtConstraint.mjCNSTR_LIMIT_TENDON)
"""``efc_type`` of a tendon-limit constraint row."""

SLIDE = int(mujoco.mjtJoint.mjJNT_SLIDE)
"""``jnt_type`` of a slide joint."""


def _jacobian_row(model: mujoco.MjModel, data: mujoco.MjData, row: int) -> npt.NDArray[np.float64]:
    """Row ``row`` of the constraint Jacobian ``efc_J``, dense, shape (nv,)."""
    if not mujoco.mj_isSparse(model):
        return np.array(data.efc_J[row * model.nv : (row + 1) * model.nv])
    dense = np.zeros(model.nv)
    adr, nnz = int(data.efc_J_rowadr[row]), int(data.efc_J_rownnz[row])
    dense[data.efc_J_colind[adr : adr + nnz]] = data.efc_J[adr : adr + nnz]
    return dense


def tendon_spring_forces(model: mujoco.MjModel, data: mujoco.MjData) -> npt.NDArray[np.float64]:
    """The spring force of every tendon [N], as MuJoCo's passive force computes it.

    The spring acts where the length is outside ``[springlength lo, hi]``: with the stretch
    ``x`` beyond that band (negative: compressed) the force is ``-x·(k + p1·x + p2·x²)``
    (``tendon_stiffness`` k, ``tendon_stiffnesspoly`` p1, p2). Positive pushes the tendon's
    ends apart (a compressed spring), negative pulls them together.

    Returns:
        Shape (ntendon,); zero with springs disabled (``mjDSBL_SPRING``).
    """
    if model.opt.disableflags & int(mujoco.mjtDisableBit.mjDSBL_SPRING):
        return np.zeros(model.ntendon)
    length = data.ten_length
    band = model.tendon_lengthspring
    stretch = length - np.minimum(np.maximum(length, band[:, 0]), band[:, 1])
    poly = model.tendon_stiffnesspoly  # (ntendon, 2): p1, p2
    stiffness = model.tendon_stiffness + stretch * (poly[:, 0] + stretch * poly[:, 1])
    result: npt.NDArray[np.float64] = -stretch * stiffness
    return result


def constraint_forces(
    model: mujoco.MjModel, data: mujoco.MjData, limit: int = MAX_CONSTRAINT_FORCES
) -> npt.NDArray[np.float64]:
    """The forces of the physics that act at a place without a contact: hard stops (joint
    limits) and loaded tendons (a press tool on its part).

    - An active limit of a slide joint (``mjCNSTR_LIMIT_JOINT``): at the joint's anchor on the
      moving body, along the joint axis, the force with which the stop pushes the body (its row
      of ``efc_J`` times ``efc_force``: the joint's share of ``qfrc_constraint``). Limits of
      hinge and ball joints are torques and are left out.
    - A spatial tendon under load: its spring force (:func:`tendon_spring_forces`) plus the
      force of its active length limit (``mjCNSTR_LIMIT_TENDON``, what a ``tendonlimitfrc``
      sensor reads), at the tendon's first path point along its first segment: the force its
      first end exerts towards the next path point (a compressed tendon, e.g. a tool pressing a
      part, points at the next point; a tendon in tension away from it). Fixed tendons act on
      joints, not at a place, and are left out.

    Args:
        model: The compiled model.
        data: Its state after a step or ``mj_forward`` (constraint forces current).
        limit: Rows returned at most (the joint limits first, then the tendons).

    Returns:
        One row per force, shape (n, :data:`CONTACT_FIELDS`): the point of action in world
        coordinates [m], then the force vector [N] in world coordinates.
    """
    rows: list[npt.NDArray[np.float64]] = []
    types = np.asarray(data.efc_type)
    forces = np.asarray(data.efc_force)
    tendon_limit = np.zeros(model.ntendon)
    for row in np.flatnonzero(((types == LIMIT_JOINT) | (types == LIMIT_TENDON)) & (forces != 0)):
        i = int(data.efc_id[row])
        if types[row] == LIMIT_JOINT:
            if int(model.jnt_type[i]) == SLIDE:
                dof = int(model.jnt_dofadr[i])
                axial = _jacobian_row(model, data, int(row))[dof] * forces[row]
                rows.append(np.concatenate([data.xanchor[i], axial * data.xaxis[i]]))
            continue
        adr, nnz = int(model.ten_J_rowadr[i]), int(model.ten_J_rownnz[i])
        ten_j = np.asarray(data.ten_J[adr : adr + nnz])
        along = _jacobian_row(model, data, int(row))[model.ten_J_colind[adr : adr + nnz]] @ ten_j
        norm = float(ten_j @ ten_j)
        if norm > 0.0:
            tendon_limit[i] += along / norm * forces[row]  # +: the limit lengthens the tendon
    if model.ntendon:
        total = tendon_spring_forces(model, data) + tendon_limit
        points = np.asarray(data.wrap_xpos).reshape(-1, 3)
        for loaded in np.flatnonzero(total != 0.0):
            adr, num = int(data.ten_wrapadr[loaded]), int(data.ten_wrapnum[loaded])
            if num < 2:  # a fixed tendon: it acts on joints, not at a place
                continue
            segment = points[adr + 1] - points[adr]
            length = float(np.linalg.norm(segment))
            if length > 0.0:
                rows.append(np.concatenate([points[adr], total[loaded] / length * segment]))
    n = min(len(rows), max(int(limit), 0))
    return np.array(rows[:n]).reshape(n, CONTACT_FIELDS)


@dataclass(frozen=True, slots=True)
class GhostAxis:
    """A driven axis as the ghost sees it.

    Attributes:
        name: Axis name in the scene (``"X"``).
        qpos_adr: Address of its joint coordinate in ``qpos``.
        scale: User units per joint unit (e.g. 1000 mm per m).
    """

    name: str
    qpos_adr: int
    scale: float


def ghost_axes(
    model: mujoco.MjModel, scene: str, joints: Sequence[tuple[str, str]]
) -> tuple[GhostAxis, ...]:
    """The driven axes of a machine with their joint addresses and unit scales.

    Args:
        model: The compiled model of the scene.
        scene: Registry name of the machine (its definition gives the axes' units).
        joints: ``(axis name, joint name)`` of every driven axis.

    Returns:
        One :class:`GhostAxis` per entry, in order.

    Raises:
        KeyError: If a joint is not in the model or an axis not in the machine definition.
    """
    definition = scenes.definition(scene)
    axes = []
    for name, joint in joints:
        j = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, joint)
        if j < 0:
            raise KeyError(f"axis {name}: the model has no joint {joint!r}")
        rotary = int(model.jnt_type[j]) == int(mujoco.mjtJoint.mjJNT_HINGE)
        _, scale = unit_and_scale(definition.scene_axes[name], rotary)
        axes.append(GhostAxis(name, int(model.jnt_qposadr[j]), scale))
    return tuple(axes)


def moved_bodies(model: mujoco.MjModel, qpos_adrs: Sequence[int]) -> list[int]:
    """Ids of the bodies that move with the given joints: each joint's body and its subtree.

    Args:
        model: The compiled model.
        qpos_adrs: ``qpos`` addresses of the joints.

    Returns:
        Body ids in increasing order.
    """
    adrs = set(qpos_adrs)
    joint_bodies = {
        int(model.jnt_bodyid[j]) for j in range(model.njnt) if int(model.jnt_qposadr[j]) in adrs
    }
    parents = np.asarray(model.body_parentid)
    moved = []
    for b in range(1, model.nbody):
        k = b
        while k != 0 and k not in joint_bodies:
            k = int(parents[k])
        if k != 0:
            moved.append(b)
    return moved


class SetPointGhost:
    """A translucent copy of the bodies the driven axes move, posed at the axes' set points.

    Args:
        model: The compiled model.
        server: The viser server whose scene receives the ghost.
        axes: The driven axes (:func:`ghost_axes`); an axis without a drive has no set point.
        prefix: Node path of the ghost's root frame.
    """

    def __init__(
        self,
        model: mujoco.MjModel,
        server: viser.ViserServer,
        axes: Sequence[GhostAxis],
        prefix: str = "/ghost",
    ) -> None:
        self._model = model
        self._data = mujoco.MjData(model)
        self._axes = tuple(axes)
        self._adrs = np.array([a.qpos_adr for a in self._axes], dtype=np.intp)
        self._scales = np.array([a.scale for a in self._axes], dtype=np.float64)
        mujoco.mj_kinematics(model, self._data)
        self.scene = ModelScene(
            model,
            server,
            prefix=prefix,
            data=self._data,
            bodies=moved_bodies(model, [a.qpos_adr for a in self._axes]),
            color=GHOST_COLOR,
            opacity=GHOST_OPACITY,
        )
        """The ghost's scene nodes (its ``root`` shows or hides it)."""

    @property
    def axes(self) -> tuple[GhostAxis, ...]:
        """The axes whose set points pose the ghost."""
        return self._axes

    def set_point_qpos(
        self, qpos: npt.NDArray[np.float64], following_errors: Sequence[float]
    ) -> npt.NDArray[np.float64]:
        """Joint coordinates with every ghost axis at its set point.

        Args:
            qpos: Measured joint coordinates [m, rad], shape (nq,).
            following_errors: Set point minus actual position of each axis of :attr:`axes`
                [user units].

        Returns:
            A copy of ``qpos`` in which each axis joint is moved by its following error.
        """
        q = np.array(qpos, dtype=np.float64)
        q[self._adrs] += np.asarray(following_errors, dtype=np.float64) / self._scales
        return q

    def update(self, qpos: npt.NDArray[np.float64], following_errors: Sequence[float]) -> None:
        """Pose the ghost at the set points (forward kinematics of a scratch ``MjData``) and send
        the bodies that moved.

        Args:
            qpos: Measured joint coordinates [m, rad], shape (nq,).
            following_errors: Set point minus actual position of each axis of :attr:`axes`
                [user units].
        """
        data = self._data
        data.qpos[:] = self.set_point_qpos(qpos, following_errors)
        mujoco.mj_kinematics(self._model, data)
        self.scene.update(data)

    @property
    def visible(self) -> bool:
        """Whether the ghost is shown."""
        return bool(self.scene.root.visible)

    @visible.setter
    def visible(self, visible: bool) -> None:
        if bool(self.scene.root.visible) != visible:
            self.scene.root.visible = visible

    def body_position(self, body: str) -> npt.NDArray[np.float64]:
        """World position [m] of a body of the ghost as last posed.

        Raises:
            KeyError: If the model has no such body.
        """
        return np.array(self._data.body(body).xpos)

    def remove(self) -> None:
        """Remove the ghost's nodes from the scene."""
        self.scene.remove()


def force_text(force: float) -> str:
    """The magnitude of a force as a label shows it: ``"74.7 kN"`` from 1 kN on, else
    ``"559 N"``."""
    magnitude = abs(force)
    return f"{magnitude / 1e3:.1f} kN" if magnitude >= 1e3 else f"{magnitude:.0f} N"


class ForceMarks:
    """One kind of force mark: a sphere at each point of action and an arrow along the force,
    at most ``capacity`` of them, in two scene nodes that are reused every frame; optionally a
    label with the force's magnitude at each point, drawn over the machine (a stop inside a
    carriage, a tool in its part), in at most ``capacity`` label nodes made as needed and
    reused.

    Args:
        server: The viser server.
        prefix: Node path of the nodes (``{prefix}points``, ``{prefix}forces``,
            ``{prefix}label_{i}``).
        color: Colour of spheres and arrows (RGB in [0, 255]).
        capacity: Marks drawn at most (the first rows).
        scale: Arrow length per newton [m/N].
        labels: Label each point with the force's magnitude (:func:`force_text`).
    """

    def __init__(
        self,
        server: viser.ViserServer,
        prefix: str,
        color: tuple[int, int, int],
        capacity: int,
        scale: float,
        labels: bool = False,
    ) -> None:
        self._server = server
        self._prefix = prefix
        self._capacity = capacity
        self._scale = scale
        self._labelled = labels
        self._labels: list[viser.LabelHandle] = []
        self._shown = np.zeros((0, CONTACT_FIELDS))
        self._points = server.scene.add_point_cloud(
            f"{prefix}points",
            points=np.zeros((1, 3), dtype=np.float32),
            colors=color,
            point_size=CONTACT_POINT_SIZE,
            point_shape="circle",
            precision="float32",
            point_shading="gradient",
            visible=False,
        )
        self._arrows = server.scene.add_arrows(
            f"{prefix}forces",
            points=np.zeros((1, 2, 3), dtype=np.float32),
            colors=color,
            shaft_radius=0.003,
            head_radius=0.008,
            head_length=0.016,
            visible=False,
        )

    @property
    def scale(self) -> float:
        """Arrow length per newton [m/N]."""
        return self._scale

    @scale.setter
    def scale(self, scale: float) -> None:
        if scale != self._scale:
            self._scale = scale
            if self._shown.shape[0]:
                self._arrows.points = self.arrows().astype(np.float32)

    @property
    def drawn(self) -> npt.NDArray[np.float64]:
        """The marks drawn now: rows of point [m] and force [N] (a copy)."""
        return self._shown.copy()

    def arrows(self) -> npt.NDArray[np.float64]:
        """Start and end point [m] of every force arrow drawn now, shape (n, 2, 3)."""
        shown = self._shown
        return np.stack([shown[:, :3], shown[:, :3] + self.scale * shown[:, 3:]], axis=1)

    @property
    def labels(self) -> list[str]:
        """The texts of the labels shown now, one per mark (none without labels)."""
        return [label.text for label in self._labels if label.visible]

    def show(self, rows: npt.NDArray[np.float64]) -> None:
        """Draw these rows (point [m], force [N]), the first ``capacity`` of them; nothing is
        sent if they are the ones drawn already."""
        rows = np.asarray(rows, dtype=np.float64).reshape(-1, CONTACT_FIELDS)[: self._capacity]
        previous = self._shown
        self._shown = rows
        if rows.shape[0] == 0:
            if previous.shape[0]:
                with self._server.atomic():
                    self._points.visible = False
                    self._arrows.visible = False
                    self._show_labels(rows)
            return
        if previous.shape == rows.shape and np.array_equal(previous, rows):
            return
        with self._server.atomic():
            self._points.points = rows[:, :3].astype(np.float32)
            self._arrows.points = self.arrows().astype(np.float32)
            if not previous.shape[0]:
                self._points.visible = True
                self._arrows.visible = True
            self._show_labels(rows)

    def _show_labels(self, rows: npt.NDArray[np.float64]) -> None:
        """Label each row's point with its force; hide the labels left over."""
        if not self._labelled:
            return
        for i, row in enumerate(rows):
            text = force_text(float(np.linalg.norm(row[3:])))
            if i == len(self._labels):
                self._labels.append(
                    self._server.scene.add_label(
                        f"{self._prefix}label_{i}",
                        text,
                        position=row[:3],
                        font_screen_scale=1.0,
                        depth_test=False,
                        anchor="bottom-left",
                    )
                )
                continue
            label = self._labels[i]
            if label.text != text:
                label.text = text
            if not np.array_equal(label.position, row[:3]):
                label.position = row[:3]
            if not label.visible:
                label.visible = True
        for label in self._labels[len(rows) :]:
            if label.visible:
                label.visible = False

    def remove(self) -> None:
        """Remove the nodes from the scene."""
        self._points.remove()
        self._arrows.remove()
        for label in self._labels:
            label.remove()
        self._labels.clear()


class ContactOverlay:
    """The forces of the physics, drawn on demand: contacts (:func:`contact_forces`, at most
    :data:`MAX_CONTACTS`) and hard stops and loaded tendons (:func:`constraint_forces`, at most
    :data:`MAX_CONSTRAINT_FORCES`, in :data:`CONSTRAINT_COLOR`, each labelled with its
    magnitude over the machine), each kind in scene nodes that are reused every frame
    (:class:`ForceMarks`).

    Args:
        server: The viser server.
        prefix: Node path of the overlay: ``{prefix}/points`` and ``{prefix}/forces`` for the
            contacts, ``{prefix}/constraint_points``, ``{prefix}/constraint_forces`` and
            ``{prefix}/constraint_label_{i}`` for the stops and tendons.
        scale: Arrow length per newton [m/N].
    """

    def __init__(
        self, server: viser.ViserServer, prefix: str = "/contacts", scale: float = 1e-4
    ) -> None:
        self._enabled = False
        self._contacts = ForceMarks(server, f"{prefix}/", CONTACT_COLOR, MAX_CONTACTS, scale)
        self._constraints = ForceMarks(
            server,
            f"{prefix}/constraint_",
            CONSTRAINT_COLOR,
            MAX_CONSTRAINT_FORCES,
            scale,
            labels=True,
        )

    @property
    def scale(self) -> float:
        """Arrow length per newton [m/N]."""
        return self._contacts.scale

    @scale.setter
    def scale(self, scale: float) -> None:
        self._contacts.scale = scale
        self._constraints.scale = scale

    @property
    def enabled(self) -> bool:
        """Whether forces are drawn (off: nothing is drawn and nothing is sent)."""
        return self._enabled

    @enabled.setter
    def enabled(self, enabled: bool) -> None:
        self._enabled = enabled
        if not enabled:
            self._contacts.show(np.zeros((0, CONTACT_FIELDS)))
            self._constraints.show(np.zeros((0, CONTACT_FIELDS)))

    @property
    def drawn(self) -> npt.NDArray[np.float64]:
        """The contacts drawn now: rows of contact point [m] and normal force [N] (a copy)."""
        return self._contacts.drawn

    @property
    def drawn_constraints(self) -> npt.NDArray[np.float64]:
        """The stop and tendon forces drawn now: rows of point [m] and force [N] (a copy)."""
        return self._constraints.drawn

    def arrows(self) -> npt.NDArray[np.float64]:
        """Start and end point [m] of every contact force arrow drawn now, shape (n, 2, 3)."""
        return self._contacts.arrows()

    def constraint_arrows(self) -> npt.NDArray[np.float64]:
        """Start and end point [m] of every stop and tendon force arrow drawn now, (n, 2, 3)."""
        return self._constraints.arrows()

    @property
    def constraint_labels(self) -> list[str]:
        """The magnitudes shown at the stop and tendon forces now (``"74.7 kN"``)."""
        return self._constraints.labels

    def update(
        self,
        contacts: npt.NDArray[np.float64],
        constraints: npt.NDArray[np.float64] | None = None,
    ) -> None:
        """Draw these forces if enabled: :func:`contact_forces` rows (the first
        :data:`MAX_CONTACTS`) and :func:`constraint_forces` rows (the first
        :data:`MAX_CONSTRAINT_FORCES`; None: none)."""
        if self._enabled:
            self._contacts.show(contacts)
            self._constraints.show(
                np.zeros((0, CONTACT_FIELDS)) if constraints is None else constraints
            )

    def remove(self) -> None:
        """Remove the overlay's nodes from the scene."""
        self._contacts.remove()
        self._constraints.remove()

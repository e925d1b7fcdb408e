"""Regenerate ``icub_upper_body.urdf`` from the official iCub models.

Sources (both CC BY-SA 4.0, robotology/icub-models; see ``PROVENANCE.md``):

- the trunk, neck, head and right arm (kinematics, joint limits, masses, inertias) come from
  ``iCubGazeboV2_5/model.urdf`` of the ``icub-models`` PyPI package (found through
  ``icub_models.get_model_file``);
- the fingers and the eyes come from ``iCubGazeboV2_5_visuomanip/model.urdf`` of the same
  repository, whose path is given on the command line (the PyPI models have neither).

What the script does to them:

- keeps only the upper body the paper uses (section III-A): torso (3), neck (3), right arm (7) and
  the right hand; legs, left arm and every frame-only link are left out;
- lumps bodies joined by fixed joints into their parent (``r_upper_arm`` into ``r_shoulder_3``,
  the finger bases ``r_hand_*_0`` into ``r_hand``), with the finger abduction and thumb
  opposition joints fixed at the angles of ``FIXED_FINGER_ANGLES``, so that every body left is
  moved by a joint;
- keeps the 15 flexion joints (``r_hand_<finger>_{1,2,3}_joint``): the world drives them all from
  the one hand motor;
- adds ``head_camera``: a frame at the midpoint of the eyes with the eyes' orientation at zero
  vergence (+z along the optical axis, +x to the right, +y down);
- replaces the meshes with primitive collision and visual shapes (boxes and spheres), sized from
  the joint offsets.

Usage::

    python skeletons/build_skeleton.py PATH/TO/iCubGazeboV2_5_visuomanip.urdf
"""

from __future__ import annotations

import argparse
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np

OUT = Path(__file__).with_name("icub_upper_body.urdf")

TRUNK_ARM_HEAD = [
    "torso_pitch", "torso_roll", "torso_yaw",
    "neck_pitch", "neck_roll", "neck_yaw",
    "r_shoulder_pitch", "r_shoulder_roll", "r_shoulder_yaw", "r_elbow",
    "r_wrist_prosup", "r_wrist_pitch", "r_wrist_yaw",
]
FINGERS = ["thumb", "index", "middle", "ring", "little"]
# Angles (rad) at which the non-flexion finger joints are welded. Abduction 0 keeps the fingers
# parallel; the thumb's opposition (iCub's thumb_oppose, limits [0, pi/2]) is 0.3 rad: open, the
# thumb lies near the palm's plane (clear of a ball in front of the palm); flexed, it crosses it.
FIXED_FINGER_ANGLES = {"thumb": 0.3, "index": 0.0, "middle": 0.0, "ring": 0.0, "little": 0.0}
PHALANX_WIDTH = 0.014  # m, square section of a phalanx box
TINY_MASS = 1e-4  # kg, for the camera frame


# ---------------------------------------------------------------- homogeneous transforms
def rpy_matrix(r: float, p: float, y: float) -> np.ndarray:
    cr, sr, cp, sp, cy, sy = np.cos(r), np.sin(r), np.cos(p), np.sin(p), np.cos(y), np.sin(y)
    return np.array([
        [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
        [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
        [-sp, cp * sr, cp * cr],
    ])


def matrix_rpy(R: np.ndarray) -> tuple[float, float, float]:
    p = np.arcsin(-np.clip(R[2, 0], -1.0, 1.0))
    if abs(np.cos(p)) > 1e-9:
        return float(np.arctan2(R[2, 1], R[2, 2])), float(p), float(np.arctan2(R[1, 0], R[0, 0]))
    return float(np.arctan2(-R[1, 2], R[1, 1])), float(p), 0.0


def transform(xyz, rpy) -> np.ndarray:
    T = np.eye(4)
    T[:3, :3] = rpy_matrix(*rpy)
    T[:3, 3] = xyz
    return T


def axis_rotation(axis, angle: float) -> np.ndarray:
    a = np.asarray(axis, float) / np.linalg.norm(axis)
    K = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    T = np.eye(4)
    T[:3, :3] = np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K
    return T


def floats(text: str | None, default="0 0 0") -> list[float]:
    return [float(v) for v in (text or default).split()]


def origin_of(elem) -> np.ndarray:
    o = elem.find("origin")
    if o is None:
        return np.eye(4)
    return transform(floats(o.get("xyz")), floats(o.get("rpy")))


# ---------------------------------------------------------------- inertia bookkeeping
class Inertial:
    """Mass (kg), centre of mass (m) and inertia about it (kg m^2), in the link frame."""

    def __init__(self, mass: float, com: np.ndarray, inertia: np.ndarray):
        self.mass, self.com, self.inertia = mass, com, inertia

    @classmethod
    def from_urdf(cls, link) -> "Inertial":
        el = link.find("inertial")
        T = origin_of(el)
        i = el.find("inertia").attrib
        I_local = np.array([
            [float(i["ixx"]), float(i["ixy"]), float(i["ixz"])],
            [float(i["ixy"]), float(i["iyy"]), float(i["iyz"])],
            [float(i["ixz"]), float(i["iyz"]), float(i["izz"])],
        ])
        R = T[:3, :3]
        return cls(float(el.find("mass").get("value")), T[:3, 3].copy(), R @ I_local @ R.T)

    def moved(self, T: np.ndarray) -> "Inertial":
        """The same body seen from a frame in which its link frame sits at pose ``T``."""
        R = T[:3, :3]
        return Inertial(self.mass, R @ self.com + T[:3, 3], R @ self.inertia @ R.T)

    def __add__(self, other: "Inertial") -> "Inertial":
        m = self.mass + other.mass
        c = (self.mass * self.com + other.mass * other.com) / m
        total = np.zeros((3, 3))
        for part in (self, other):
            d = part.com - c
            total += part.inertia + part.mass * (d @ d * np.eye(3) - np.outer(d, d))
        return Inertial(m, c, total)


# ---------------------------------------------------------------- URDF writing
def fmt(values) -> str:
    return " ".join(f"{v:.12g}" for v in values)


def add_inertial(link, inertial: Inertial) -> None:
    el = ET.SubElement(link, "inertial")
    ET.SubElement(el, "origin", xyz=fmt(inertial.com), rpy="0 0 0")
    ET.SubElement(el, "mass", value=f"{inertial.mass:.12g}")
    I = inertial.inertia
    ET.SubElement(el, "inertia", ixx=f"{I[0, 0]:.12g}", ixy=f"{I[0, 1]:.12g}",
                  ixz=f"{I[0, 2]:.12g}", iyy=f"{I[1, 1]:.12g}", iyz=f"{I[1, 2]:.12g}",
                  izz=f"{I[2, 2]:.12g}")


def add_shape(link, T: np.ndarray, geometry: tuple, rgba: str) -> None:
    """One primitive as both collision and visual geometry, posed at T in the link frame."""
    kind, *dims = geometry
    for tag in ("collision", "visual"):
        el = ET.SubElement(link, tag)
        ET.SubElement(el, "origin", xyz=fmt(T[:3, 3]), rpy=fmt(matrix_rpy(T[:3, :3])))
        geo = ET.SubElement(el, "geometry")
        if kind == "box":
            ET.SubElement(geo, "box", size=fmt(dims))
        else:
            ET.SubElement(geo, "sphere", radius=f"{dims[0]:.12g}")
        if tag == "visual":
            ET.SubElement(ET.SubElement(el, "material", name=f"{link.get('name')}_{tag}"),
                          "color", rgba=rgba)


def segment_box(start, end, width: float) -> tuple[np.ndarray, tuple]:
    """A box of square section ``width`` whose long axis (x) runs from ``start`` to ``end``."""
    start, end = np.asarray(start, float), np.asarray(end, float)
    d = end - start
    length = float(np.linalg.norm(d))
    x = d / length
    helper = np.array([0.0, 0.0, 1.0]) if abs(x[2]) < 0.9 else np.array([1.0, 0.0, 0.0])
    y = np.cross(helper, x)
    y /= np.linalg.norm(y)
    T = np.eye(4)
    T[:3, :3] = np.column_stack([x, y, np.cross(x, y)])
    T[:3, 3] = (start + end) / 2
    return T, ("box", length, width, width)


def add_joint(robot, name, kind, parent, child, T, axis=None, limit=None) -> None:
    j = ET.SubElement(robot, "joint", name=name, type=kind)
    ET.SubElement(j, "origin", xyz=fmt(T[:3, 3]), rpy=fmt(matrix_rpy(T[:3, :3])))
    if axis is not None:
        ET.SubElement(j, "axis", xyz=fmt(axis))
    ET.SubElement(j, "parent", link=parent)
    ET.SubElement(j, "child", link=child)
    if limit is not None:
        ET.SubElement(j, "limit", effort="50000", velocity="50000",
                      lower=f"{limit[0]:.12g}", upper=f"{limit[1]:.12g}")


# ---------------------------------------------------------------- the build
def build(official_path: Path, visuomanip_path: Path) -> ET.Element:
    off = ET.parse(official_path).getroot()
    vm = ET.parse(visuomanip_path).getroot()
    off_links = {l.get("name"): l for l in off.findall("link")}
    off_joints = {j.get("name"): j for j in off.findall("joint")}
    vm_links = {l.get("name"): l for l in vm.findall("link")}
    vm_joints = {j.get("name"): j for j in vm.findall("joint")}

    def limit(j):
        lim = j.find("limit")
        return float(lim.get("lower")), float(lim.get("upper"))

    robot = ET.Element("robot", name="icub_upper_body")
    links: dict[str, ET.Element] = {}
    inertials: dict[str, Inertial] = {}

    def new_link(name: str, inertial: Inertial) -> ET.Element:
        links[name] = ET.SubElement(robot, "link", name=name)
        inertials[name] = inertial
        return links[name]

    new_link("root_link", Inertial.from_urdf(off_links["root_link"]))
    # Revolute joints of the trunk, neck and arm; r_upper_arm (fixed joint r_arm_ft_sensor) is
    # lumped into r_shoulder_3 and r_elbow re-expressed from r_shoulder_3.
    ft = off_joints["r_arm_ft_sensor"]
    T_ft = origin_of(ft)
    for name in TRUNK_ARM_HEAD:
        j = off_joints[name]
        parent, child = j.find("parent").get("link"), j.find("child").get("link")
        T = origin_of(j)
        if parent == "r_upper_arm":
            parent, T = "r_shoulder_3", T_ft @ T
        inertial = Inertial.from_urdf(off_links[child])
        if child == "r_shoulder_3":
            inertial = inertial + Inertial.from_urdf(off_links["r_upper_arm"]).moved(T_ft)
        new_link(child, inertial)
        add_joint(robot, name, "revolute", parent, child, T, floats(j.find("axis").get("xyz")),
                  limit(j))

    # Fingers: the base link of each finger (joint *_0: abduction, or the thumb's opposition)
    # is welded at FIXED_FINGER_ANGLES and lumped into r_hand.
    hand_extra = []
    for finger in FINGERS:
        j0 = vm_joints[f"r_hand_{finger}_0_joint"]
        T_base = origin_of(j0) @ axis_rotation(floats(j0.find("axis").get("xyz")),
                                                FIXED_FINGER_ANGLES[finger])
        hand_extra.append(Inertial.from_urdf(vm_links[f"r_hand_{finger}_0"]).moved(T_base))
        parent, T_parent = "r_hand", T_base
        for k in (1, 2, 3):
            j = vm_joints[f"r_hand_{finger}_{k}_joint"]
            child = f"r_hand_{finger}_{k}"
            new_link(child, Inertial.from_urdf(vm_links[child]))
            add_joint(robot, f"{child}_joint", "revolute", parent, child, T_parent @ origin_of(j),
                      floats(j.find("axis").get("xyz")), limit(j))
            parent, T_parent = child, np.eye(4)
    for extra in hand_extra:
        inertials["r_hand"] = inertials["r_hand"] + extra

    # Camera frame: midpoint of the eyes (eyes_tilt_frame) with the eye's orientation at zero
    # tilt and pan: +z along the optical axis, +x right, +y down.
    T_tilt = origin_of(vm_joints["eyes_tilt"])
    T_eye = T_tilt @ origin_of(vm_joints["r_eye_pan_joint"])
    T_cam = np.eye(4)
    T_cam[:3, :3] = T_eye[:3, :3]
    T_cam[:3, 3] = T_tilt[:3, 3]
    new_link("head_camera", Inertial(TINY_MASS, np.zeros(3), np.eye(3) * 1e-8))
    add_joint(robot, "head_camera_fixed_joint", "fixed", "head", "head_camera", T_cam)

    for name, link in links.items():
        add_inertial(link, inertials[name])
    add_shapes(links, robot)
    return robot


def child_origin(robot, child_joint: str) -> np.ndarray:
    for j in robot.findall("joint"):
        if j.get("name") == child_joint:
            return floats(j.find("origin").get("xyz"))
    raise KeyError(child_joint)


def add_shapes(links: dict, robot) -> None:
    """Primitive shapes, placed from the joint offsets of the kinematic chain."""
    grey, dark, white = "0.85 0.85 0.85 1", "0.25 0.25 0.25 1", "0.95 0.95 0.95 1"
    o = lambda joint: np.asarray(child_origin(robot, joint))  # noqa: E731

    # Trunk: chest frame has y up the spine; the shoulders sit at x = -/+0.12 (right/left).
    T = np.eye(4)
    T[:3, 3] = [0.0, 0.07, -0.035]
    add_shape(links["chest"], T, ("box", 0.17, 0.17, 0.10), grey)
    T = np.eye(4)
    T[:3, 3] = [0.0, 0.085, 0.03]  # head: a sphere around the eyes and skull
    add_shape(links["head"], T, ("sphere", 0.065), white)
    # Arm segments between consecutive joints.
    T, g = segment_box(np.zeros(3), o("r_elbow"), 0.05)
    add_shape(links["r_shoulder_3"], T, g, grey)
    T, g = segment_box(np.zeros(3), o("r_wrist_pitch"), 0.045)
    add_shape(links["r_forearm"], T, g, grey)
    # Palm: spans from the wrist to the finger bases; its normal is the fingers' closing side.
    bases = np.array([o(f"r_hand_{f}_1_joint") for f in FINGERS[1:]])
    lo, hi = bases.min(axis=0), bases.max(axis=0)
    T = np.eye(4)
    T[:3, 3] = [(lo[0] - 0.005) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2]
    add_shape(links["r_hand"], T, ("box", -lo[0] + 0.005, 0.02, hi[2] - lo[2] + PHALANX_WIDTH),
              dark)
    # Phalanges: a box from the joint to the next joint (distal: to the fingertip).
    for finger in FINGERS:
        for k in (1, 2, 3):
            end = o(f"r_hand_{finger}_{k + 1}_joint") if k < 3 else np.array([0.0168, 0, 0])
            T, g = segment_box(np.zeros(3), end, PHALANX_WIDTH)
            add_shape(links[f"r_hand_{finger}_{k}"], T, g, dark if k < 3 else white)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("visuomanip", type=Path, help="iCubGazeboV2_5_visuomanip URDF")
    parser.add_argument("--out", type=Path, default=OUT)
    args = parser.parse_args(argv)
    import icub_models  # the dev extra

    official = Path(icub_models.get_model_file("iCubGazeboV2_5"))
    robot = build(official, args.visuomanip)
    ET.indent(robot)
    header = (
        "<?xml version=\"1.0\"?>\n"
        "<!-- Generated by skeletons/build_skeleton.py from the iCub models of robotology/\n"
        "     icub-models (iCubGazeboV2_5 from the icub-models PyPI package; fingers and eyes from\n"
        "     iCubGazeboV2_5_visuomanip). CC BY-SA 4.0, see skeletons/PROVENANCE.md.\n"
        "     Do not edit by hand: regenerate. -->\n"
    )
    args.out.write_text(header + ET.tostring(robot, encoding="unicode") + "\n")
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

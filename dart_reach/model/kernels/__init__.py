"""The living model's compiled kernels (model versions 2 and 3, ``versions.Numerics.COMPILED``),
one module per concept of the paper's section III, each read against its section:

- ``network``: the network's update equation and its logistic (section III-B, Fig. 3), the
  motor targets 2 m - 1, ``CompiledNetwork``;
- ``sensing``: the 25 sensors (section III-B, Eqs. 1-4), the fitness terms p_sight, p_touch
  and p_multimodal (section III-C, Eq. 5) and a trial's record row;
- ``motors``: the motor commands under the servo's speed cap and the springs' joint forces
  (section III-B);
- ``touch``: the inner-face touch of the 16 hand segments (sections III-B, III-C);

and what they share: ``floats`` (the exponential and the clip, rounded alike on every
processor), ``kinematics`` (the bodies' world poses from the joint positions, which the
sensing and the touch read) and ``structures`` (the Numba structures a step function reads
its arrays through). ``model.compiled`` composes them into the trial's step functions and
states the rounding rules every kernel follows.

Every kernel is compiled with Numba (``cache=True``: its machine code is cached beside its
module) and runs as the plain Python it is written in when ``NUMBA_DISABLE_JIT=1`` is set
before Python starts, to the same bits, for debugging (docs/model/trial.md, "Running the
compiled model uncompiled").

Units: angles in rad (visual angles in degrees, Eq. 4), lengths in m, forces in N m, poses
as 4x4 homogeneous transforms in the world frame.
"""

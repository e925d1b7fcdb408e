"""Model version 1, frozen: the code that reproduces every run trained under it, bit for bit.

Used only to resume, evaluate and reproduce version 1's runs (``Settings(model_version=1)``,
the environment ``ReachGrasp-v1``, a shipped robot of version 1): ``task.steps_for`` and
``task.network_for`` build its steps and network for a trial of ``versions.Numerics.
REFERENCE``. The living model (the versions new runs use) is ``model.compiled``,
``model.servo`` and ``model.compiled_trial``; nothing outside ``task`` imports this folder.

- ``network``: the network's update (section III-B, Fig. 3), numpy's kernels;
- ``sensors``: the sensor encodings (Eqs. 1-4) and the fitness terms (Eq. 5), Python floats;
- ``servo``: the motors driven by the springs' rest positions and the physics substeps, the
  touches gathered on Python floats (``ReferenceServo``, ``inner_face_touch``);
- ``steps``: one control step of a trial (``ReferenceSteps``: sense, act, command, advance).

What it shares with the living model (the DART world and its layout, the network's parameters
and reflexes, the sensors' constants, ``ctrnn.motor_targets``) lives in ``model``; tests/model/
test_reference_frozen.py pins every file of this folder and that shared code by digests.
These files are never edited: a change to the model is a new model version
(docs/model/trial.md, "How to change the model").
"""

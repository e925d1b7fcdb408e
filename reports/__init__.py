"""The project's studies of its own runs: pages generated from the committed tables under
recordings/ into docs/results/. Not part of the installed package; imports ``dart_reach`` one
way (the package never imports this folder). Run from the repository's root:
``python -m reports.<study>`` (``make results`` runs ``reports.results``, which renders every
templated page).

- ``results``: every page rendered from its template in docs/results/templates/, and the
  findings frames committed beside the runs; ``--check`` names the pages that differ;
- ``pre_reaching_course``, ``stillness``, ``cost``: the values of their pages;
- ``scene_study``: the scene study's contrasts, tables and figure (``python -m
  reports.scene_study``);
- ``levers``: the levers study's page; ``calibration``: the verdict rules' calibration table;
- ``campaign``: the second pre-registration, the scene's calibration and the campaign's page;
- ``babbling_sample``, ``babbling_second_sample``, ``babbling_third_sample``: the trials drawn
  for labelling by eye; ``babbling_validation``: the detector checked on them;
  ``babbling_detector``: the detector's page (docs/results/babbling-detector.md);
  ``babbling_before_touch``: babbling before the first touch (claim A1);
- ``runs``: the committed runs the pages read and the generations judged; ``text``: the
  templates' placeholders and the pages' tables (numbers: ``dart_reach.analysis.formatting``).
"""

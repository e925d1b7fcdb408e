"""The project's studies of its own runs: pages generated from the committed tables under
recordings/ into docs/results/. Not part of the installed package; imports ``dart_reach`` one
way. Run from the repository's root: ``python -m reports.<study>`` (``make results``)."""

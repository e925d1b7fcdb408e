"""The suite computes as a user's session does: ``import dart_reach`` pins OpenBLAS's kernels and
numpy's dispatch level only if it comes before numpy is loaded, so it comes first here."""

import dart_reach  # noqa: F401

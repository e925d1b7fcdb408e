"""dart_reach: the reaching-and-grasping development model of Savastano & Nolfi (IEEE TAMD 2013)
on a DART-simulated iCub upper body."""

__version__ = "0.1.0"

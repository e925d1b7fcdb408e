"""The project's committed runs that its pages read (folders under recordings/), and the
generations at which the full-budget run's pre-reachers are judged."""

from __future__ import annotations

#: The ten-replication run: the standard condition at 50 generations per phase, gross^ at
#: 100, 10 replications as the paper's, so that the replication can be the unit of every
#: verdict.
TEN = "replication-50x10"
#: The replication runs of docs/results/replication.md, smallest budget first.
REPLICATIONS = ("replication-10", "replication-50", TEN)
#: The paper's full budget: the standard condition, 500 generations per phase, 10
#: replications; trained over many sessions.
FULL = "standard-500x10"
#: The run whose final pre-reachers were taken apart first (docs/results/stillness.md): the
#: best 5 of each of its 10 replications.
STILLNESS_RUN = TEN
#: The generations of ``FULL``'s pre-reaching at which the claims of pre-reachers are judged
#: (every condition evaluated there, the robots run again for Eq. 5's terms): every 50th to
#: this round's end, generation 250. The Makefile's JUDGED lists the same.
JUDGED = (50, 100, 150, 200, 250)

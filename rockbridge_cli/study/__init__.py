"""Running a study: its grid of analyses (`grid`), the work a worker does (`work`), where the
work runs (`executors`), the crash-safe journal of finished analyses (`journal`), and the run
that ties them to the results file (`run`)."""

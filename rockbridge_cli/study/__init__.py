"""Running a study: its grid of analyses (`grid`) and the rounds it runs them in (`plan`), the
work a worker does (`work`) with its compiled kernels (`kernels`), where the work runs
(`executors`), the crash-safe journal of finished analyses (`journal`), the description of the
study its results file stores (`describe`; written while the run goes on, `prewritten`), the
run that ties them to the results file (`run`), array jobs' shards (`shards`) and their merge
(`merge`), the lock that lets one run or merge write a results file at a time (`output_lock`),
and the one analysis of `rockbridge analyze` by the same route (`single`)."""

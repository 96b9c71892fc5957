"""What is computed from a results file, never by running an analysis: the limit states an
analysis reached (`limit_states`), the rule of incremental dynamic analysis (`ida`), the lognormal
fragility fits (`fragility`, by the maximum likelihood of `lognormal`), their bootstrap intervals
and the records needed to settle them (`fragility_intervals`), which sampled bridge field matters
(`sensitivity`) and the fragility folded over the samples (`sampled_fragility`), how a peak
table's analyses form summaries per bridge and level (`levels`), IDA capacities in another
intensity measure (`measures`) and which measure predicts them best (`efficiency`), a site's
hazard curve (`hazard`) and the annual frequency of each limit state there (`risk`), and the
exports to OpenQuake and pelicun (`exports`); an overturning spectrum's map and boundaries
(`spectrum`); the median and worst demand over the angles a pair was swept (`orientation`) and
the fragility each angle a record against the pairs' median and worst (`orientation_fragility`)."""

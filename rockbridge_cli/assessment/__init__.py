"""What is computed from a results file, never by running an analysis: the limit states an
analysis reached (`limit_states`), the rule of incremental dynamic analysis (`ida`) and the
lognormal fragility fits (`fragility`)."""

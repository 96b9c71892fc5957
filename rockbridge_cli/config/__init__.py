"""YAML configs validated by pydantic: bridges (`bridge`, with its `devices`), record sets
(`record_sets`), record selections (`selection`) and studies (`study`: its resolution into a
`study.Study`; the models of its file: `study_models`; its record sources, files, FEMA P695 sets
or pulses: `records`, with the direction its bridge feels each pair of horizontal components in:
`orientation`; its `intensity`, `sweep`, `uncertainty` and `spectrum` sections; its records
resolved: `study_records`; its checks as a whole: `study_checks`); `loading` reads a file and
reports its problems, `plausibility` warns of legal but implausible values, and `changes` says
what differs between two resolved studies (`rockbridge_cli.kinds` names the kind of file given
where another was expected)."""

"""YAML configs validated by pydantic: bridges (`bridge`), record sets (`records`), record
selections (`selection`), the direction a study's bridge feels its pairs of horizontal components
in (`orientation`, a section of a study's records) and studies (`study`, with its `intensity`,
`sweep`, `uncertainty` and `spectrum` sections, its records resolved: `study_records`, and its
checks as a whole: `study_checks`); `loading` reads a file and reports its problems,
`plausibility` warns of legal but implausible values, and `changes` says what differs between
two resolved studies (`rockbridge_cli.kinds` names the kind of file given where another was
expected)."""

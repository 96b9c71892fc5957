"""YAML configs validated by pydantic: bridges (`bridge`), record sets (`records`), record
selections (`selection`) and studies (`study`, with its `intensity`, `sweep`, `uncertainty` and
`spectrum` sections, and its records resolved: `study_records`); `loading` reads a file and reports
its problems, `kinds` names the kind of file given where another was expected, `plausibility` warns
of legal but implausible values, and `changes` says what differs between two resolved studies."""

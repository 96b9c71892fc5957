"""YAML configs validated by pydantic: bridges (`bridge`), record sets (`records`) and studies
(`study`, with its `intensity` and `sweep` sections); `loading` reads a file and reports its
problems."""

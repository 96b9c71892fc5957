"""Placeholder: commands are added as the issues land."""

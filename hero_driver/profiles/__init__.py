"""The HERO 2000 profile: knowledge file, recorded training data, example library."""

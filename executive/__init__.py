"""executive."""

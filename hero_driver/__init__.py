"""hero_driver."""

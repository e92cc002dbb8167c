"""hero_driver/sim."""

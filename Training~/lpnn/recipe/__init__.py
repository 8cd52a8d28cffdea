"""The reproducible recipe that trains the shipped model on OpenArena levels (Documentation~/training.md,
"The default model"): levels -> volume-sized crops -> reference labels -> training -> held-out evaluation."""

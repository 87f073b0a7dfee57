"""Adapters to other libraries, each an optional extra and imported on its own:
``saggriac.adapters.gym`` (Gymnasium: a goal-conditioned arm, a Gymnasium env as a body, a
teacher choosing an env's goals), ``saggriac.adapters.sb3`` (Stable-Baselines3: one teacher for
every worker of a vectorised env) and ``saggriac.adapters.syllabus`` (Syllabus: saggriac's
teachers as curricula). Importing this package loads none of them."""

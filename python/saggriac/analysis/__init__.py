"""What is made of finished runs and studies: the statistics table (statistics), the figures
(plots) and the null model of where the region tree splits (splits).

Import the module you need (``from saggriac.analysis import statistics``): they bring scipy and
matplotlib, which a run does not need."""

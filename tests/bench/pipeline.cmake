set(bench_pipeline_LIBS lasonic_stages lasonic_sim)
# The shipped scene and configuration are read from the source tree.
set(bench_pipeline_DEFINITIONS LASONIC_SOURCE_DIR="${PROJECT_SOURCE_DIR}")

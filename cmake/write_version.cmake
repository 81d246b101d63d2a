# Writes generated/slipstrip/version.hpp with the git hash of the source tree
# *at build time*.  Run on every build (target slipstrip_version): a hash taken
# only at configure time goes stale after the next commit, and then every output
# file would name the wrong code.  configure_file leaves the header untouched
# when nothing changed, so an unchanged tree recompiles nothing.
# Inputs: SOURCE_DIR, OUTPUT, TEMPLATE, PROJECT_VERSION.
execute_process(COMMAND git rev-parse --short=12 HEAD
  WORKING_DIRECTORY ${SOURCE_DIR} OUTPUT_VARIABLE SLIPSTRIP_GIT_HASH
  OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET RESULT_VARIABLE rev_status)
if(NOT rev_status EQUAL 0 OR NOT SLIPSTRIP_GIT_HASH)
  set(SLIPSTRIP_GIT_HASH "unknown")
else()
  # Uncommitted changes to tracked files: the hash alone would not say which code ran.
  execute_process(COMMAND git status --porcelain --untracked-files=no
    WORKING_DIRECTORY ${SOURCE_DIR} OUTPUT_VARIABLE tree_changes
    OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
  if(tree_changes)
    string(APPEND SLIPSTRIP_GIT_HASH "-dirty")
  endif()
endif()
configure_file(${TEMPLATE} ${OUTPUT} @ONLY)

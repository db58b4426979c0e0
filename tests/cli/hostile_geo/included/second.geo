// The second script of the Include and Merge cases: it would run a command (test_hostile_geo
// checks that no marker file appears).
SystemCall "touch second_script_ran";

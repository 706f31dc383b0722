"""./kit report: a class report from a saved grading (index.html and a page per student).

The modules: grading.py reads a saved grading (the CSV and the students' JSON); signatures.py holds
which cases each mutant of tests/mutants/ fails and matches a student's failing cases against them;
similar.py ranks similar submissions with Debian's similarity-tester (sim_c++); plots.py draws the
charts (as SVG, by charts.py, the kit's one drawing path); pages.py writes the HTML.
"""

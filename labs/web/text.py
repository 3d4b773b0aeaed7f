"""The page's own words, in English and Russian (the labs' words come from their specs)."""

TEXT = {
    "en": {
        "title": "dynlab — lab measurements to reports",
        "labs": "Labs", "choose": "Choose your lab, fill in what you measured, press Reduce.",
        "open": "Open a measurement file to edit it: its .toml with the files it names (select them all), or the .zip downloaded from this page",
        "open_button": "Open", "meta": "Who and where",
        "student": "Student", "group": "Group", "date": "Date", "rig": "Rig", "notes": "Notes",
        "required": "required", "optional": "optional", "add": "Add", "remove": "Remove",
        "entry": "Entry", "reduce": "Reduce", "unit": "unit",
        "kept": "already attached", "attach": "photograph, film or recording",
        "numbers": "Numbers take a decimal comma or point: 36,07 or 36.07. Repeated readings: "
                   "36,07; 36,21; 36,22. A value may carry its own unit: \"850 ± 0,5 mm\".",
        "error_top": "The measurement was not reduced",
        "report": "Report", "downloads": "Download", "pdf": "PDF report",
        "json": "Result JSON", "zip": "Measurement file (TOML and its files, .zip)",
        "edit": "Edit these values", "back": "All labs", "html": "HTML report",
        "reduced_in": "reduced in", "s": "s",
        "hand_in": "Hand in to the teacher", "roster_id": "Your id in the class roster",
        "reported": "The values you got, one a line: name = value unit "
                    "(names as in the report, e.g. J_trifilar = 0,1978 kg*m^2)",
        "hand_in_button": "Hand in", "handed_in": "Handed in under id",
        "class": "Class", "class_title": "The class's hand-ins",
        "class_summary": "Summary of dynlab check", "handins": "Hand-ins", "id": "Id",
        "name": "Name", "lab": "Labs handed in", "time": "Time", "checking": "checking…",
        "files": "Download", "command": "Made by",
        "forbidden": "This form has expired or did not come from this page. Reload the page "
                     "and send it again.",
        "not_found": "There is no such page (a submission is kept for two hours).",
        "busy": "Every worker is busy; please send the form again in a minute.",
        "file_too_large": "A file is larger than this page takes",
        "submission_too_large": "The files together are larger than this page takes in one "
                                "submission.",
        "report_missing": "The report could not be made in time.",
        "bad_zip": "This is not a measurement this page can open.",
        "unknown_student": "That id is not in the class roster.",
        "failed": "The reduction failed", "no_token":
            "This page needs the link with its token: ask your teacher for it.",
        "limits": "Limits",
    },
    "ru": {
        "title": "dynlab — от измерений к отчёту",
        "labs": "Лабораторные работы",
        "choose": "Выберите работу, впишите измеренное, нажмите «Обработать».",
        "open": "Открыть файл измерений для правки: его .toml вместе с файлами, которые в нём названы (выберите все), или .zip, скачанный с этой страницы",
        "open_button": "Открыть", "meta": "Кто и где",
        "student": "Студент", "group": "Группа", "date": "Дата", "rig": "Стенд",
        "notes": "Примечания", "required": "обязательно", "optional": "необязательно",
        "add": "Добавить", "remove": "Удалить", "entry": "Запись", "reduce": "Обработать",
        "unit": "единица", "kept": "уже приложен", "attach": "фото, видео или запись",
        "numbers": "Числа — с десятичной запятой или точкой: 36,07 или 36.07. Повторные "
                   "отсчёты: 36,07; 36,21; 36,22. Значение может нести свою единицу: "
                   "«850 ± 0,5 мм».",
        "error_top": "Измерение не обработано",
        "report": "Отчёт", "downloads": "Скачать", "pdf": "Отчёт PDF",
        "json": "Результат JSON", "zip": "Файл измерений (TOML и его файлы, .zip)",
        "edit": "Исправить значения", "back": "Все работы", "html": "Отчёт HTML",
        "reduced_in": "обработано за", "s": "с",
        "hand_in": "Сдать преподавателю", "roster_id": "Ваш номер в списке группы",
        "reported": "Полученные вами значения, по одному в строке: имя = значение единица "
                    "(имена как в отчёте, например J_trifilar = 0,1978 kg*m^2)",
        "hand_in_button": "Сдать", "handed_in": "Сдано под номером",
        "class": "Группа", "class_title": "Сданные работы группы",
        "class_summary": "Сводка dynlab check", "handins": "Сдано", "id": "Номер",
        "name": "Имя", "lab": "Сданные работы", "time": "Время", "checking": "проверяется…",
        "files": "Скачать", "command": "Получено командой",
        "forbidden": "Форма устарела или пришла не с этой страницы. Обновите страницу и "
                     "отправьте её снова.",
        "not_found": "Такой страницы нет (работа хранится два часа).",
        "busy": "Все обработчики заняты; отправьте форму снова через минуту.",
        "file_too_large": "Файл больше, чем принимает эта страница",
        "submission_too_large": "Файлы вместе больше, чем страница принимает за одну отправку.",
        "report_missing": "Отчёт не удалось сделать вовремя.",
        "bad_zip": "Это не измерение, которое может открыть эта страница.",
        "unknown_student": "Такого номера нет в списке группы.",
        "failed": "Обработка не удалась", "no_token":
            "Эта страница открывается по ссылке с ключом: спросите её у преподавателя.",
        "limits": "Ограничения",
    },
}
"""The page's words by language."""
